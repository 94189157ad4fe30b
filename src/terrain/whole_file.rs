//! The heightmap formats written whole: 32-bit float OpenEXR (the `exr` crate) and 32-bit
//! float TIFF (the `tiff` crate). Both encoders seek back to write offsets, so the image is
//! encoded in memory and then copied to the output.

use std::io::Cursor;

/// One-channel (`Y`) 32-bit float OpenEXR: ZIP-compressed scan lines in increasing order,
/// encoded on one thread so the bytes do not depend on the thread count.
///
/// # Errors
/// The encoder's error, as an I/O error.
pub fn exr(values: Vec<f32>, width: u32, height: u32) -> std::io::Result<Vec<u8>> {
    use exr::prelude::*;
    let size = (width as usize, height as usize);
    let channel = AnyChannel::new("Y", FlatSamples::F32(values));
    let encoding =
        Encoding { compression: Compression::ZIP16, blocks: Blocks::ScanLines, line_order: LineOrder::Increasing };
    let layer =
        Layer::new(size, LayerAttributes::named("height"), encoding, AnyChannels::sort(smallvec::smallvec![channel]));
    let mut bytes = Cursor::new(Vec::new());
    Image::from_layer(layer).write().non_parallel().to_buffered(&mut bytes).map_err(std::io::Error::other)?;
    Ok(bytes.into_inner())
}

/// Baseline 32-bit float greyscale TIFF (SampleFormat IEEE float), uncompressed strips;
/// BigTIFF when the pixels pass 4 GB.
///
/// # Errors
/// The encoder's error, as an I/O error.
pub fn tiff(values: &[f32], width: u32, height: u32) -> std::io::Result<Vec<u8>> {
    use tiff::encoder::{TiffEncoder, colortype::Gray32Float};
    let mut bytes = Cursor::new(Vec::new());
    let result = if values.len() as u64 * 4 >= 0xF000_0000 {
        TiffEncoder::new_big(&mut bytes).and_then(|mut e| e.write_image::<Gray32Float>(width, height, values))
    } else {
        TiffEncoder::new(&mut bytes).and_then(|mut e| e.write_image::<Gray32Float>(width, height, values))
    };
    result.map_err(std::io::Error::other)?;
    Ok(bytes.into_inner())
}
