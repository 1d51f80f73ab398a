//! A KTX2 file (Khronos) of one level of uncompressed float texels: what
//! the volume exports write (Bevy's ambient-cube texture, the textures the
//! volume shader snippets read).
//!
//! One level, one layer, one face, no supercompression; a basic data format
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

/// The KTX2 file of `data` (texels of `format`, little-endian, x fastest,
/// then y, then z) of `size` = width, height, depth.
///
/// # Panics
/// If `data` is not `width x height x depth` texels of `format`.
#[must_use]
pub fn write_ktx2(format: Ktx2Format, size: [usize; 3], data: &[u8], writer: &str) -> Vec<u8> {
    const IDENTIFIER: [u8; 12] = [
        0xAB, 0x4B, 0x54, 0x58, 0x20, 0x32, 0x30, 0xBB, 0x0D, 0x0A, 0x1A, 0x0A,
    ];
    let (channels, bytes) = (format.channels(), format.channel_bytes());
    assert_eq!(
        data.len(),
        size.iter().product::<usize>() * channels * bytes,
        "texels of a {size:?} texture"
    );
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
    // (3 u64), the descriptor, the key/values, then the level, 8-aligned.
    let header_len = 12 + 9 * 4 + 4 * 4 + 2 * 8 + 3 * 8;
    let dfd_offset = header_len;
    let kvd_offset = dfd_offset + dfd.len();
    let level_offset = (kvd_offset + kvd.len()).div_ceil(8) * 8;
    let mut out = Vec::with_capacity(level_offset + data.len());
    out.extend(IDENTIFIER);
    for v in [
        format.vk_format(),
        bytes as u32, // typeSize
        size[0] as u32,
        size[1] as u32,
        if size[2] > 1 { size[2] as u32 } else { 0 },
        0, // layers: not an array
        1, // faces
        1, // levels
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
    out.extend((level_offset as u64).to_le_bytes());
    out.extend((data.len() as u64).to_le_bytes());
    out.extend((data.len() as u64).to_le_bytes());
    out.extend(&dfd);
    out.extend(&kvd);
    out.resize(level_offset, 0);
    out.extend(data);
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
}
