//! Textures shlight writes: KTX2 (a prefiltered cube with mips, Bevy's
//! irradiance volume, the textures of a volume's shader snippet) and
//! Filament's KTX 1.1 cube, told apart by their headers' format, faces and
//! shape (and a volume snippet's textures by their names).

use super::Header;
use crate::{FormatError, GL_R11F_G11F_B10F, Ktx2Format, Result};

/// The KTX2 file identifier.
const KTX2: [u8; 12] = [
    0xAB, 0x4B, 0x54, 0x58, 0x20, 0x32, 0x30, 0xBB, 0x0D, 0x0A, 0x1A, 0x0A,
];
/// The KTX 1.1 file identifier.
const KTX1: [u8; 12] = [
    0xAB, 0x4B, 0x54, 0x58, 0x20, 0x31, 0x31, 0xBB, 0x0D, 0x0A, 0x1A, 0x0A,
];

/// A KTX2 or KTX 1.1 file; `None` for bytes without either identifier.
pub(super) fn describe(bytes: &[u8], name: &str) -> Result<Option<Header>> {
    if bytes.starts_with(&KTX2) {
        return ktx2(bytes, name).map(Some);
    }
    if bytes.starts_with(&KTX1) {
        return ktx1(bytes, name).map(Some);
    }
    Ok(None)
}

/// The little-endian `u32` at `at`, or an error saying the file ends early.
fn word(bytes: &[u8], at: usize, name: &str, what: &str) -> Result<u32> {
    bytes
        .get(at..at + 4)
        .map(|b| u32::from_le_bytes([b[0], b[1], b[2], b[3]]))
        .ok_or_else(|| truncated(bytes, name, what))
}

fn truncated(bytes: &[u8], name: &str, what: &str) -> FormatError {
    FormatError::invalid(
        name,
        format!("a truncated {what} file (it ends at byte {})", bytes.len()),
    )
}

/// Mip 0's size and the smallest mip's, `W x H` (and `x D`).
fn mips(size: [u32; 3], levels: u32) -> String {
    let last = levels.saturating_sub(1);
    let at = |k: u32| {
        let [w, h, d] = size.map(|s| s.checked_shr(k).unwrap_or(0).max(1));
        if size[2] > 0 {
            format!("{w}x{h}x{d}")
        } else {
            format!("{w}x{h}")
        }
    };
    if levels <= 1 {
        format!("1 level, {}", at(0))
    } else {
        format!("{levels} mips, {} down to {}", at(0), at(last))
    }
}

fn ktx2(bytes: &[u8], name: &str) -> Result<Header> {
    let what = "KTX2";
    let w = |at: usize| word(bytes, at, name, what);
    let vk = w(12)?;
    let size = [w(20)?, w(24)?, w(28)?];
    let (layers, faces, levels, scheme) = (w(32)?, w(36)?, w(40)?, w(44)?);
    let (kvd_at, kvd_len) = (w(56)? as usize, w(60)? as usize);
    // Every level's bytes must be in the file.
    for k in 0..levels as usize {
        let at = 80 + 24 * k;
        let offset = u64::from(w(at)?) | u64::from(w(at + 4)?) << 32;
        let length = u64::from(w(at + 8)?) | u64::from(w(at + 12)?) << 32;
        if offset.saturating_add(length) > bytes.len() as u64 {
            return Err(truncated(bytes, name, what));
        }
    }
    let kvd = bytes
        .get(kvd_at..kvd_at.saturating_add(kvd_len))
        .ok_or_else(|| truncated(bytes, name, what))?;
    let writer = key_value(kvd, "KTXwriter");
    let format = [
        Ktx2Format::Rgba16Float,
        Ktx2Format::Rg32Float,
        Ktx2Format::Rgba32Float,
    ]
    .into_iter()
    .find(|f| f.vk_format() == vk);
    let [width, height, depth] = size;
    let file = name.to_ascii_lowercase();
    let role = |suffix: &str| file.ends_with(&format!(".{suffix}.ktx2"));
    let (kind, holds) = match format {
        Some(Ktx2Format::Rgba16Float) if faces == 6 => (
            "a cube map with mips (shlight prefilter -o FILE.ktx2): the environment \
             prefiltered with the GGX lobe, Bevy's EnvironmentMapLight specular map"
                .to_string(),
            format!(
                "6 faces (+X -X +Y -Y +Z -Z), {}, linear RGB with alpha 1",
                mips(size, levels)
            ),
        ),
        Some(Ktx2Format::Rgba16Float) if depth > 0 && height % 2 == 0 && depth % 3 == 0 => (
            "Bevy IrradianceVolume texture (shlight volume --format bevy): a volume's \
             ambient cubes"
                .to_string(),
            format!(
                "a {width} x {} x {} grid of probes, each six colours E(+-axis) / pi at \
                 texel (x, y + ny s, z + nz axis)",
                height / 2,
                depth / 3
            ),
        ),
        Some(Ktx2Format::Rgba32Float) if role("sh") => (
            "a volume snippet's sh texture (shlight convert VOLUME -o NAME.wgsl|glsl)".into(),
            format!(
                "texel (x, y, i nz + z) = (v L_i, v): coefficient i of probe (x, y, z) times \
                 its validity v; {depth} slices = (lmax+1)^2 x nz"
            ),
        ),
        Some(Ktx2Format::Rgba32Float) if role("probes") => (
            "a volume snippet's probes texture (shlight convert VOLUME -o NAME.wgsl|glsl)".into(),
            format!("a {width} x {height} x {depth} grid: each probe's position and validity"),
        ),
        Some(Ktx2Format::Rg32Float) if role("moments") => (
            "a volume snippet's moments texture (shlight convert VOLUME -o NAME.wgsl|glsl)".into(),
            format!(
                "each probe's octahedral map of (mean, mean_sq) distance in a tile with a \
                 one-texel border; {depth} slices (nz)"
            ),
        ),
        _ => ("a KTX2 texture".to_string(), String::new()),
    };
    let mut h = Header::new(format!("KTX2: {kind}"));
    if !holds.is_empty() {
        h.field("holds", holds);
    }
    h.field(
        "format",
        match format {
            Some(Ktx2Format::Rgba16Float) => {
                "VK_FORMAT_R16G16B16A16_SFLOAT (RGBA half floats)".to_string()
            }
            Some(Ktx2Format::Rg32Float) => "VK_FORMAT_R32G32_SFLOAT (RG 32-bit floats)".into(),
            Some(Ktx2Format::Rgba32Float) => {
                "VK_FORMAT_R32G32B32A32_SFLOAT (RGBA 32-bit floats)".into()
            }
            None => format!("VkFormat {vk}"),
        },
    );
    h.field(
        "size",
        if depth > 0 {
            format!("{width} x {height} x {depth} (3D)")
        } else {
            format!("{width} x {height}")
        },
    );
    h.field("faces", faces.to_string());
    h.field("levels", levels.to_string());
    if layers > 0 {
        h.field("layers", layers.to_string());
    }
    if scheme != 0 {
        h.field("supercompression", format!("scheme {scheme}"));
    }
    if let Some(writer) = writer {
        h.field("writer", writer);
    }
    Ok(h)
}

/// The value of `key` in a KTX2 key/value block.
fn key_value(kvd: &[u8], key: &str) -> Option<String> {
    let mut at = 0;
    while at + 4 <= kvd.len() {
        let n = u32::from_le_bytes([kvd[at], kvd[at + 1], kvd[at + 2], kvd[at + 3]]) as usize;
        let entry = kvd.get(at + 4..at + 4 + n)?;
        let split = entry.iter().position(|&b| b == 0)?;
        if &entry[..split] == key.as_bytes() {
            let value = &entry[split + 1..];
            let value = value.strip_suffix(&[0]).unwrap_or(value);
            return Some(String::from_utf8_lossy(value).into_owned());
        }
        at += (4 + n).next_multiple_of(4);
    }
    None
}

fn ktx1(bytes: &[u8], name: &str) -> Result<Header> {
    let what = "KTX 1.1";
    let w = |at: usize| word(bytes, at, name, what);
    if w(12)? != 0x0403_0201 {
        return Err(FormatError::invalid(
            name,
            "a KTX 1.1 file in big-endian byte order, which shlight never writes",
        ));
    }
    let internal = w(28)?;
    let size = [w(36)?, w(40)?, w(44)?];
    let (elements, faces, levels, kvd) = (w(48)?, w(52)?, w(56)?, w(60)? as usize);
    // Each level: its image size, then its faces, each padded to 4 bytes.
    let mut at = 64usize.saturating_add(kvd);
    for _ in 0..levels.max(1) {
        let image = w(at)? as usize;
        let per = if faces == 6 && elements == 0 {
            6 * image.next_multiple_of(4)
        } else {
            image.next_multiple_of(4)
        };
        at = at.saturating_add(4).saturating_add(per);
        if at > bytes.len() {
            return Err(truncated(bytes, name, what));
        }
    }
    let filament = internal == GL_R11F_G11F_B10F && faces == 6;
    let mut h = Header::new(if filament {
        "KTX 1.1: Filament's prefiltered cube map (shlight prefilter -o FILE.ktx, as cmgen \
         --format=ktx writes it for its KtxBundle)"
    } else {
        "KTX 1.1 texture"
    });
    h.field(
        "format",
        if internal == GL_R11F_G11F_B10F {
            "GL_R11F_G11F_B10F (packed 11-11-10-bit floats)".to_string()
        } else {
            format!("glInternalFormat 0x{internal:04X}")
        },
    );
    h.field("faces", faces.to_string());
    h.field("levels", mips(size, levels.max(1)));
    Ok(h)
}
