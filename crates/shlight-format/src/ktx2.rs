//! KTX2 files (Khronos) of uncompressed float texels: what the volume
//! exports write (Bevy's ambient-cube texture, the textures the volume
//! shader snippets read) and the prefiltered cube maps with mips
//! ([`cube_map_ktx2`], Bevy's `EnvironmentMapLight`).
//!
//! One layer, one face (or six for a cube map), no supercompression; a basic data format
//! descriptor (RGBSDA colour model, BT.709 primaries, linear transfer, one
//! sample per channel, signed float) and a `KTXwriter` key. A depth above 1
//! makes a 3D texture.

/// The texel formats written.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Ktx2Format {
    /// `VK_FORMAT_R16G16B16A16_SFLOAT`: four half floats.
    Rgba16Float,
    /// `VK_FORMAT_R32G32_SFLOAT`: two floats.
    Rg32Float,
    /// `VK_FORMAT_R32G32B32A32_SFLOAT`: four floats.
    Rgba32Float,
}

impl Ktx2Format {
    /// The Vulkan format number KTX2 names it by.
    #[must_use]
    pub fn vk_format(self) -> u32 {
        match self {
            Ktx2Format::Rgba16Float => 97,
            Ktx2Format::Rg32Float => 103,
            Ktx2Format::Rgba32Float => 109,
        }
    }

    /// Channels per texel.
    #[must_use]
    pub fn channels(self) -> usize {
        match self {
            Ktx2Format::Rg32Float => 2,
            _ => 4,
        }
    }

    /// Bytes per channel.
    #[must_use]
    pub fn channel_bytes(self) -> usize {
        match self {
            Ktx2Format::Rgba16Float => 2,
            _ => 4,
        }
    }
}

/// A cube map with mips as KTX2: `levels[k][f]` the `s_k x s_k` linear RGB
/// texels (row-major, row 0 at the top) of face `f` (`+X -X +Y -Y +Z -Z`,
/// the Vulkan cube-map convention) of mip `k`, `s_k = size >> k`; stored as
/// half floats (round to nearest even) with alpha 1 (what Bevy's
/// `EnvironmentMapLight` takes as its specular map). `writer` goes in the
/// `KTXwriter` key.
///
/// # Panics
/// When a face does not hold `s_k * s_k` texels.
#[must_use]
pub fn cube_map_ktx2(size: usize, levels: &[[Vec<[f32; 3]>; 6]], writer: &str) -> Vec<u8> {
    let data: Vec<Vec<u8>> = levels
        .iter()
        .enumerate()
        .map(|(k, faces)| {
            let s = (size >> k).max(1);
            faces
                .iter()
                .flat_map(|face| {
                    assert_eq!(face.len(), s * s, "mip {k}: a face of {s}x{s} texels");
                    face.iter().flat_map(|p| {
                        [p[0], p[1], p[2], 1.0]
                            .into_iter()
                            .flat_map(|v| half::f16::from_f32(v).to_bits().to_le_bytes())
                    })
                })
                .collect()
        })
        .collect();
    write_ktx2_levels(Ktx2Format::Rgba16Float, [size, size, 1], 6, &data, writer)
}

/// The KTX2 file of one level of `data` (texels of `format`,
/// little-endian, x fastest, then y, then z) of `size` = width, height,
/// depth.
///
/// # Panics
/// If `data` is not `width x height x depth` texels of `format`.
#[must_use]
pub fn write_ktx2(format: Ktx2Format, size: [usize; 3], data: &[u8], writer: &str) -> Vec<u8> {
    assert_eq!(
        data.len(),
        size.iter().product::<usize>() * format.channels() * format.channel_bytes(),
        "texels of a {size:?} texture"
    );
    write_ktx2_levels(
        format,
        size,
        1,
        std::slice::from_ref(&data.to_vec()),
        writer,
    )
}

/// A KTX2 file of texels of `format`: `size` = width, height, depth of
/// level 0 (a depth above 1 makes a 3D texture), `faces` 1 or 6 (a cube
/// map), `levels[k]` the bytes of mip `k` (its faces one after another,
/// `+X -X +Y -Y +Z -Z`). Levels are stored smallest first, each 8-byte
/// aligned, as the KTX2 specification lays them out.
fn write_ktx2_levels(
    format: Ktx2Format,
    size: [usize; 3],
    faces: u32,
    levels: &[Vec<u8>],
    writer: &str,
) -> Vec<u8> {
    const IDENTIFIER: [u8; 12] = [
        0xAB, 0x4B, 0x54, 0x58, 0x20, 0x32, 0x30, 0xBB, 0x0D, 0x0A, 0x1A, 0x0A,
    ];
    let (channels, bytes) = (format.channels(), format.channel_bytes());
    // Data format descriptor: total size, then one basic block of 24 bytes
    // plus 16 per sample (one per channel: R, G, B, A).
    let mut dfd = Vec::new();
    let block_size = (24 + 16 * channels) as u16;
    dfd.extend((4 + u32::from(block_size)).to_le_bytes());
    dfd.extend(0u32.to_le_bytes()); // vendor 0 (Khronos), descriptor type 0 (basic)
    dfd.extend(2u16.to_le_bytes()); // version 1.3 of the descriptor
    dfd.extend(block_size.to_le_bytes());
    dfd.extend([1, 1, 1, 0]); // RGBSDA model, BT.709 primaries, linear transfer, straight alpha
    dfd.extend([0, 0, 0, 0]); // texel block 1 x 1 x 1 x 1
    dfd.extend([(channels * bytes) as u8, 0, 0, 0, 0, 0, 0, 0]); // bytes per texel, one plane
    for (k, channel) in [0u8, 1, 2, 15].into_iter().take(channels).enumerate() {
        dfd.extend(((8 * bytes * k) as u16).to_le_bytes()); // bit offset
        dfd.push((8 * bytes - 1) as u8); // bit length - 1
        dfd.push(channel | 0x80 | 0x40); // float, signed
        dfd.extend([0, 0, 0, 0]); // sample position
        dfd.extend((-1.0f32).to_bits().to_le_bytes()); // sample lower
        dfd.extend(1.0f32.to_bits().to_le_bytes()); // sample upper
    }
    let mut kvd = Vec::new();
    let entry = [b"KTXwriter\0".as_slice(), writer.as_bytes(), b"\0"].concat();
    kvd.extend((entry.len() as u32).to_le_bytes());
    kvd.extend(&entry);
    while kvd.len() % 4 != 0 {
        kvd.push(0);
    }
    // Layout: identifier, header (9 u32), index (4 u32 + 2 u64), level index
    // (3 u64 per level), the descriptor, the key/values, then the levels,
    // smallest first, each 8-aligned.
    let header_len = 12 + 9 * 4 + 4 * 4 + 2 * 8 + 3 * 8 * levels.len();
    let dfd_offset = header_len;
    let kvd_offset = dfd_offset + dfd.len();
    let mut offsets = vec![0usize; levels.len()];
    let mut end = kvd_offset + kvd.len();
    for k in (0..levels.len()).rev() {
        end = end.div_ceil(8) * 8;
        offsets[k] = end;
        end += levels[k].len();
    }
    let mut out = Vec::with_capacity(end);
    out.extend(IDENTIFIER);
    for v in [
        format.vk_format(),
        bytes as u32, // typeSize
        size[0] as u32,
        size[1] as u32,
        if size[2] > 1 { size[2] as u32 } else { 0 },
        0, // layers: not an array
        faces,
        levels.len() as u32,
        0, // no supercompression
    ] {
        out.extend(v.to_le_bytes());
    }
    out.extend((dfd_offset as u32).to_le_bytes());
    out.extend((dfd.len() as u32).to_le_bytes());
    out.extend((kvd_offset as u32).to_le_bytes());
    out.extend((kvd.len() as u32).to_le_bytes());
    out.extend(0u64.to_le_bytes()); // no supercompression global data
    out.extend(0u64.to_le_bytes());
    for (offset, data) in offsets.iter().zip(levels) {
        out.extend((*offset as u64).to_le_bytes());
        out.extend((data.len() as u64).to_le_bytes());
        out.extend((data.len() as u64).to_le_bytes());
    }
    out.extend(&dfd);
    out.extend(&kvd);
    for k in (0..levels.len()).rev() {
        out.resize(offsets[k], 0);
        out.extend(&levels[k]);
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;

    /// An independent reader (the `ktx2` crate) reads back each format's
    /// header, its descriptor's channels and the texels as written.
    #[test]
    fn every_format_reads_back_with_the_ktx2_crate() {
        for (format, size) in [
            (Ktx2Format::Rgba16Float, [3, 2, 1]),
            (Ktx2Format::Rg32Float, [2, 3, 4]),
            (Ktx2Format::Rgba32Float, [1, 2, 5]),
        ] {
            let texels: usize = size.iter().product();
            let data: Vec<u8> = (0..texels * format.channels() * format.channel_bytes())
                .map(|i| (i * 7 % 251) as u8)
                .collect();
            let file = write_ktx2(format, size, &data, "shlight test");
            let reader = ktx2::Reader::new(&file[..]).expect("a KTX2 file");
            let header = reader.header();
            assert_eq!(
                header.format.map(|f| f.value()),
                Some(format.vk_format()),
                "{format:?}"
            );
            assert_eq!(header.type_size as usize, format.channel_bytes());
            assert_eq!(header.pixel_width as usize, size[0]);
            assert_eq!(header.pixel_height as usize, size[1]);
            assert_eq!(
                header.pixel_depth as usize,
                if size[2] > 1 { size[2] } else { 0 }
            );
            let level = reader.levels().next().expect("one level");
            assert_eq!(level.data, &data[..]);
            let dfd = reader.dfd_blocks().next().expect("a descriptor");
            let basic = ktx2::DfdBlockBasic::parse(dfd.data).expect("basic");
            assert_eq!(basic.sample_information().count(), format.channels());
            assert_eq!(
                basic.header.bytes_planes[0] as usize,
                format.channels() * format.channel_bytes()
            );
        }
    }

    /// The `ktx2` crate (the reader Bevy loads KTX2 with) reads a cube with
    /// mips back: six faces, every level's size, each texel where it was
    /// put, and the DFD and levels where their offsets say.
    #[test]
    fn a_cube_with_mips_reads_back_through_the_ktx2_crate() {
        let size = 4;
        let levels: Vec<[Vec<[f32; 3]>; 6]> = (0..3)
            .map(|k| {
                let s = size >> k;
                std::array::from_fn(|f| {
                    (0..s * s)
                        .map(|i| [k as f32, f as f32, i as f32 + 0.5])
                        .collect()
                })
            })
            .collect();
        let bytes = cube_map_ktx2(size, &levels, "test");
        let reader = ktx2::Reader::new(&bytes[..]).expect("a valid KTX2 file");
        let h = reader.header();
        assert_eq!(h.format, Some(ktx2::Format::R16G16B16A16_SFLOAT));
        assert_eq!((h.pixel_width, h.pixel_height, h.pixel_depth), (4, 4, 0));
        assert_eq!((h.layer_count, h.face_count, h.level_count), (0, 6, 3));
        for (k, level) in reader.levels().enumerate() {
            let s = size >> k;
            assert_eq!(level.data.len(), 6 * s * s * 8);
            for (n, t) in level.data.chunks_exact(8).enumerate() {
                let c = |j: usize| {
                    half::f16::from_bits(u16::from_le_bytes([t[2 * j], t[2 * j + 1]])).to_f32()
                };
                let (f, i) = (n / (s * s), n % (s * s));
                assert_eq!(
                    [c(0), c(1), c(2), c(3)],
                    [k as f32, f as f32, i as f32 + 0.5, 1.0]
                );
            }
        }
        // Smallest level first in the file, each 8-byte aligned.
        let offsets: Vec<u64> = reader
            .levels()
            .map(|l| l.data.as_ptr() as u64 - bytes.as_ptr() as u64)
            .collect();
        assert!(offsets[2] < offsets[1] && offsets[1] < offsets[0]);
        assert!(offsets.iter().all(|o| o % 8 == 0));
    }
}
