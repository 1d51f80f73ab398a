//! The layers of an OpenEXR file, and which one to read.
//!
//! A layer is a group of channels with a common name prefix within one part:
//! `diffuse.R`, `diffuse.G`, `diffuse.B` form layer `diffuse`. In a
//! multi-part file the part's name comes first (`beauty.diffuse`; plain `R`,
//! `G`, `B` in part `beauty` form layer `beauty`). Plain channels of a
//! single-part file form the unnamed layer `""`. Channel names are matched
//! ignoring ASCII case (`R`, `G`, `B`, `Y`, `RY`, `BY`).

use exr::meta::header::Header;

use crate::IoErrorKind;

/// The channels a layer is read from: indices into its part's channel list.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(super) enum Colour {
    /// Red, green and blue channels.
    Rgb { r: usize, g: usize, b: usize },
    /// A luminance channel, read as grey.
    Grey { y: usize },
}

/// The layer to read: its part and channels.
#[derive(Clone, Copy, Debug)]
pub(super) struct Chosen {
    pub(super) part: usize,
    pub(super) colour: Colour,
}

/// One layer of the file.
struct Layer {
    name: String,
    part: usize,
    r: Option<usize>,
    g: Option<usize>,
    b: Option<usize>,
    y: Option<usize>,
    /// Has `RY` or `BY` channels (a luminance/chroma image).
    chroma: bool,
    channel_names: Vec<String>,
}

impl Layer {
    fn colour(&self) -> Option<Colour> {
        match (self.r, self.g, self.b, self.y) {
            (Some(r), Some(g), Some(b), _) => Some(Colour::Rgb { r, g, b }),
            (_, _, _, Some(y)) if !self.chroma => Some(Colour::Grey { y }),
            _ => None,
        }
    }
}

/// The layer named `wanted`, or by default the first with R, G, B channels
/// (else the first with a lone Y channel).
pub(super) fn choose(headers: &[Header], wanted: Option<&str>) -> Result<Chosen, IoErrorKind> {
    let layers = catalogue(headers);
    let layer =
        match wanted {
            Some(wanted) => layers.iter().find(|l| l.name == wanted).ok_or_else(|| {
                IoErrorKind::LayerNotFound {
                    wanted: wanted.to_owned(),
                    available: layers.iter().map(|l| l.name.clone()).collect(),
                }
            })?,
            None => layers
                .iter()
                .find(|l| matches!(l.colour(), Some(Colour::Rgb { .. })))
                .or_else(|| layers.iter().find(|l| l.colour().is_some()))
                .ok_or_else(|| {
                    let channels = layers.iter().flat_map(|l| &l.channel_names);
                    IoErrorKind::Unsupported(format!(
                        "no layer with R, G, B or Y channels (channels: {})",
                        join(channels)
                    ))
                })?,
        };
    let colour = layer.colour().ok_or_else(|| {
        let what = if layer.chroma {
            "is a luminance/chroma (Y, RY, BY) layer, which is not read"
        } else {
            "has no R, G, B or Y channels"
        };
        IoErrorKind::Unsupported(format!(
            "layer {:?} {what} (channels: {})",
            layer.name,
            join(&layer.channel_names)
        ))
    })?;
    Ok(Chosen {
        part: layer.part,
        colour,
    })
}

/// Every layer of the file, in file order; within a part, the part's own
/// (unprefixed) channel group first.
fn catalogue(headers: &[Header]) -> Vec<Layer> {
    let mut layers: Vec<Layer> = Vec::new();
    for (part, header) in headers.iter().enumerate() {
        let part_name = header
            .own_attributes
            .layer_name
            .as_ref()
            .map(|n| n.to_string())
            .unwrap_or_default();
        let first = layers.len();
        for (index, channel) in header.channels.list.iter().enumerate() {
            let full = channel.name.to_string();
            let (prefix, base) = match full.rfind('.') {
                Some(dot) => (&full[..dot], &full[dot + 1..]),
                None => ("", full.as_str()),
            };
            let name = match (part_name.is_empty(), prefix.is_empty()) {
                (_, true) => part_name.clone(),
                (true, false) => prefix.to_owned(),
                (false, false) => format!("{part_name}.{prefix}"),
            };
            let position = match layers[first..].iter().position(|l| l.name == name) {
                Some(i) => first + i,
                None => {
                    layers.push(Layer {
                        name,
                        part,
                        r: None,
                        g: None,
                        b: None,
                        y: None,
                        chroma: false,
                        channel_names: Vec::new(),
                    });
                    layers.len() - 1
                }
            };
            let layer = &mut layers[position];
            let is = |s: &str| base.eq_ignore_ascii_case(s);
            if is("R") {
                layer.r = Some(index);
            } else if is("G") {
                layer.g = Some(index);
            } else if is("B") {
                layer.b = Some(index);
            } else if is("Y") {
                layer.y = Some(index);
            } else if is("RY") || is("BY") {
                layer.chroma = true;
            }
            layer.channel_names.push(full);
        }
        // Stable: the unprefixed group first, the others in channel order.
        layers[first..].sort_by_key(|l| l.name != part_name);
    }
    layers
}

fn join<S: AsRef<str>>(items: impl IntoIterator<Item = S>) -> String {
    items
        .into_iter()
        .map(|s| s.as_ref().to_owned())
        .collect::<Vec<_>>()
        .join(", ")
}
