//! Scalar images: 16-bit greyscale PNG (values mapped linearly from a range) and raw
//! little-endian f32. Both written atomically.

use std::path::Path;

use super::write_atomically;
use crate::error::{Error, Result};

/// Writes `values` (row-major, `width` per row) as a 16-bit greyscale PNG, mapping
/// `range.0` to black and `range.1` to white (values outside are clamped).
///
/// # Errors
/// [`Error::InvalidInput`] for an empty image or an empty range; [`Error::Io`] on failure.
pub fn write_png16(path: &Path, values: &[f64], width: usize, range: (f64, f64)) -> Result<()> {
    if width == 0 || values.is_empty() || !values.len().is_multiple_of(width) {
        return Err(Error::InvalidInput(format!("{} values do not form rows of {width}", values.len())));
    }
    let (lo, hi) = range;
    if hi <= lo || !lo.is_finite() || !hi.is_finite() {
        return Err(Error::InvalidInput(format!("empty value range {lo}..{hi}")));
    }
    let height = values.len() / width;
    let mut data = Vec::with_capacity(values.len() * 2);
    for v in values {
        let t = ((v - lo) / (hi - lo)).clamp(0.0, 1.0);
        data.extend_from_slice(&((t * 65535.0).round() as u16).to_be_bytes());
    }
    let (w, h) = (u32::try_from(width), u32::try_from(height));
    let (Ok(w), Ok(h)) = (w, h) else { return Err(Error::InvalidInput("image too large for PNG".into())) };
    write_atomically(path, |out| {
        let mut encoder = png::Encoder::new(out, w, h);
        encoder.set_color(png::ColorType::Grayscale);
        encoder.set_depth(png::BitDepth::Sixteen);
        let mut writer = encoder.write_header().map_err(std::io::Error::other)?;
        writer.write_image_data(&data).map_err(std::io::Error::other)?;
        writer.finish().map_err(std::io::Error::other)
    })
}

/// Writes an 8-bit RGB PNG from row-major RGB bytes.
///
/// # Errors
/// [`Error::InvalidInput`] when the bytes do not form `width`-pixel rows; [`Error::Io`].
pub fn write_png_rgb8(path: &Path, rgb: &[u8], width: usize) -> Result<()> {
    write_png8(path, rgb, width, png::ColorType::Rgb, 3)
}

/// Writes an 8-bit RGBA PNG from row-major RGBA bytes.
///
/// # Errors
/// [`Error::InvalidInput`] when the bytes do not form `width`-pixel rows; [`Error::Io`].
pub fn write_png_rgba8(path: &Path, rgba: &[u8], width: usize) -> Result<()> {
    write_png8(path, rgba, width, png::ColorType::Rgba, 4)
}

fn write_png8(path: &Path, bytes: &[u8], width: usize, color: png::ColorType, channels: usize) -> Result<()> {
    if width == 0 || bytes.is_empty() || !bytes.len().is_multiple_of(channels * width) {
        return Err(Error::InvalidInput(format!(
            "{} bytes do not form {channels}-channel rows of {width} pixels",
            bytes.len()
        )));
    }
    let (Ok(w), Ok(h)) = (u32::try_from(width), u32::try_from(bytes.len() / (channels * width))) else {
        return Err(Error::InvalidInput("image too large for PNG".into()));
    };
    write_atomically(path, |out| {
        let mut encoder = png::Encoder::new(out, w, h);
        encoder.set_color(color);
        encoder.set_depth(png::BitDepth::Eight);
        let mut writer = encoder.write_header().map_err(std::io::Error::other)?;
        writer.write_image_data(bytes).map_err(std::io::Error::other)?;
        writer.finish().map_err(std::io::Error::other)
    })
}

/// Writes `values` as raw little-endian f32.
///
/// # Errors
/// [`Error::Io`] on failure.
pub fn write_f32(path: &Path, values: &[f64]) -> Result<()> {
    write_atomically(path, |out| {
        let bytes: Vec<u8> = values.iter().flat_map(|v| (*v as f32).to_le_bytes()).collect();
        out.write_all(&bytes)
    })
}

/// Smallest and largest finite value (`None` if there is none).
pub fn value_range(values: &[f64]) -> Option<(f64, f64)> {
    values.iter().filter(|v| v.is_finite()).fold(None, |acc, &v| match acc {
        None => Some((v, v)),
        Some((lo, hi)) => Some((lo.min(v), hi.max(v))),
    })
}
