//! glTF textures to decoded [`Texture`]s: the image (PNG or JPEG, from a
//! buffer view, a base64 data URI or a file beside the glTF file) decoded
//! to 8-bit RGBA (16-bit images reduced to 8 bits), and the sampler's
//! wrap modes and magnification filter.
//!
//! Each texture's pixel count is checked against
//! [`LoadOptions::max_texture_pixels`] from the image header before it is
//! decoded, and all the textures of a file together against 16 times that.
//! `KHR_texture_basisu` (KTX2) images are refused naming the texture, unless
//! the texture also names a PNG or JPEG fallback.

use std::collections::HashMap;
use std::io::Cursor;
use std::path::Path;

use gltf::json;
use json::texture::{MagFilter, WrappingMode};
use json::validation::Checked;

use super::accessor::{self, Data};
use super::uri;
use crate::texture::{Filter, Texture, Wrap};
use crate::{LoadOptions, MeshError};

/// Textures extensions that replace the image with one shlight does not
/// decode.
const IMAGE_EXTENSIONS: &[(&str, &str)] = &[
    ("KHR_texture_basisu", "KTX2 / Basis Universal"),
    ("EXT_texture_webp", "WebP"),
    ("EXT_texture_avif", "AVIF"),
    ("MSFT_texture_dds", "DDS"),
];

/// The textures decoded so far, each glTF texture once.
pub(super) struct Textures<'a> {
    path: &'a Path,
    data: Data<'a>,
    options: LoadOptions,
    /// The decoded textures ([`crate::Scene::textures`]).
    pub decoded: Vec<Texture>,
    /// glTF texture index to index in `decoded`.
    index: HashMap<usize, usize>,
    /// Pixels decoded so far.
    pixels: u64,
}

impl<'a> Textures<'a> {
    pub fn new(path: &'a Path, data: Data<'a>, options: LoadOptions) -> Self {
        Self {
            path,
            data,
            options,
            decoded: Vec::new(),
            index: HashMap::new(),
            pixels: 0,
        }
    }

    /// The index in [`Textures::decoded`] of glTF texture `texture`,
    /// decoding it the first time.
    pub fn get(&mut self, texture: usize) -> Result<usize, MeshError> {
        if let Some(&i) = self.index.get(&texture) {
            return Ok(i);
        }
        let t = self.decode(texture)?;
        self.decoded.push(t);
        self.index.insert(texture, self.decoded.len() - 1);
        Ok(self.decoded.len() - 1)
    }

    fn decode(&mut self, index: usize) -> Result<Texture, MeshError> {
        let root = self.data.root;
        let texture = root
            .textures
            .get(index)
            .ok_or_else(|| self.fail(format!("texture {index} does not exist")))?;
        let name = match &texture.name {
            Some(n) => format!("texture {index} ({n})"),
            None => format!("texture {index}"),
        };
        let fail = |message: String| self.fail(format!("{name}: {message}"));
        let source = texture.source.value();
        let Some(image) = root.images.get(source) else {
            let extension = texture.extensions.as_ref().and_then(|e| {
                IMAGE_EXTENSIONS
                    .iter()
                    .find(|(n, _)| e.others.contains_key(*n))
            });
            return Err(fail(match extension {
                Some((ext, what)) => format!(
                    "its image is given by {ext} ({what}), which shlight does not decode, \
                     and it has no PNG or JPEG fallback"
                ),
                None => "it has no image".into(),
            }));
        };
        let what_image = match &image.name {
            Some(n) => format!("image {source} ({n})"),
            None => format!("image {source}"),
        };
        let (bytes, file) = match (&image.buffer_view, &image.uri) {
            (Some(view), _) => (
                accessor::view(self.data, view.value())
                    .map_err(|e| fail(format!("{what_image}: {e}")))?
                    .to_vec(),
                None,
            ),
            (None, Some(u)) => {
                let (bytes, origin) =
                    uri::read(self.path, u).map_err(|e| fail(format!("{what_image}: {e}")))?;
                let file = match origin {
                    uri::Origin::File(f) => Some(f),
                    uri::Origin::Data => None,
                };
                (bytes, file)
            }
            (None, None) => {
                return Err(fail(format!(
                    "{what_image} has neither a URI nor a buffer view"
                )));
            }
        };
        let from = match &file {
            Some(f) => format!("{what_image} ({})", f.display()),
            None => what_image,
        };
        let format = match image::guess_format(&bytes) {
            Ok(f @ (image::ImageFormat::Png | image::ImageFormat::Jpeg)) => f,
            _ if bytes.starts_with(b"\xABKTX 20\xBB") => {
                return Err(fail(format!(
                    "{from} is a KTX2 image (KHR_texture_basisu), which shlight does not decode"
                )));
            }
            _ => return Err(fail(format!("{from} is not a PNG or JPEG image"))),
        };
        let reader = || image::ImageReader::with_format(Cursor::new(&bytes[..]), format);
        let (w, h) = reader()
            .into_dimensions()
            .map_err(|e| fail(format!("{from}: {e}")))?;
        let pixels = u64::from(w) * u64::from(h);
        let max = self.options.max_texture_pixels as u64;
        if pixels > max {
            return Err(MeshError::TextureTooLarge {
                path: self.path.to_path_buf(),
                texture: name,
                pixels,
                max: self.options.max_texture_pixels,
            });
        }
        let total = self.pixels + pixels;
        if total > max.saturating_mul(TOTAL_FACTOR) {
            return Err(fail(format!(
                "the file's textures hold {total} pixels or more, over {TOTAL_FACTOR} times the texture pixel limit of {max}"
            )));
        }
        if w == 0 || h == 0 {
            return Err(fail(format!("{from} has no pixels")));
        }
        let mut limits = image::Limits::default();
        limits.max_image_width = Some(w);
        limits.max_image_height = Some(h);
        limits.max_alloc = Some(pixels.saturating_mul(32).max(1 << 20));
        let mut reader = reader();
        reader.limits(limits);
        let decoded = reader.decode().map_err(|e| fail(format!("{from}: {e}")))?;
        self.pixels = total;
        let rgba = decoded.into_rgba8();
        let texels = rgba
            .as_raw()
            .chunks_exact(4)
            .map(|c| [c[0], c[1], c[2], c[3]])
            .collect();
        let sampler = texture.sampler.and_then(|s| root.samplers.get(s.value()));
        let wrap = |mode: Option<&Checked<WrappingMode>>| match mode {
            Some(Checked::Valid(WrappingMode::ClampToEdge)) => Wrap::ClampToEdge,
            Some(Checked::Valid(WrappingMode::MirroredRepeat)) => Wrap::MirroredRepeat,
            _ => Wrap::Repeat,
        };
        Ok(Texture {
            width: w as usize,
            height: h as usize,
            texels,
            wrap_u: wrap(sampler.map(|s| &s.wrap_s)),
            wrap_v: wrap(sampler.map(|s| &s.wrap_t)),
            filter: match sampler.and_then(|s| s.mag_filter.as_ref()) {
                Some(Checked::Valid(MagFilter::Nearest)) => Filter::Nearest,
                _ => Filter::Linear,
            },
        })
    }

    fn fail(&self, message: String) -> MeshError {
        MeshError::Parse {
            path: self.path.to_path_buf(),
            message,
        }
    }
}

/// All a file's textures together may hold this many times
/// [`LoadOptions::max_texture_pixels`].
pub(crate) const TOTAL_FACTOR: u64 = 16;
