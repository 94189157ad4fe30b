//! Texture images for `render --texture` (#22 B5): a PNG read into linear texels and
//! sampled bilinearly at UVs (repeating; v runs up the image, as OBJ and PLY have it).

use std::path::Path;

use glam::{Vec2, Vec3};

use crate::error::{Error, Location, Result};

/// An RGB image, rows top to bottom, channels 0 to 1.
pub struct Texture {
    width: usize,
    height: usize,
    texels: Vec<Vec3>,
}

impl std::fmt::Debug for Texture {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        write!(f, "Texture {{ {}x{} }}", self.width, self.height)
    }
}

impl Texture {
    /// A texture from rows of RGB texels (top row first).
    ///
    /// # Errors
    /// [`Error::InvalidInput`] for an empty image or a texel count that is not width × height.
    pub fn new(width: usize, height: usize, texels: Vec<Vec3>) -> Result<Self> {
        if width == 0 || height == 0 || texels.len() != width * height {
            return Err(Error::InvalidInput(format!("a {width}x{height} texture with {} texels", texels.len())));
        }
        Ok(Texture { width, height, texels })
    }

    /// Reads a PNG (grey, grey and alpha, RGB or RGBA, any bit depth; alpha ignored).
    ///
    /// # Errors
    /// [`Error::Io`] if the file cannot be read; [`Error::Parse`] naming it for a file that
    /// is not a PNG.
    pub fn read_png(path: &Path) -> Result<Self> {
        let bytes = crate::io::read_regular_file(path)?;
        let bad = |e: png::DecodingError| Error::parse(path, Location::File, format!("PNG: {e}"));
        let mut decoder = png::Decoder::new(std::io::Cursor::new(bytes));
        decoder.set_transformations(png::Transformations::EXPAND | png::Transformations::STRIP_16);
        let mut reader = decoder.read_info().map_err(bad)?;
        let mut buffer = vec![0; reader.output_buffer_size().unwrap_or(0)];
        let info = reader.next_frame(&mut buffer).map_err(bad)?;
        let channels = info.color_type.samples();
        let texels = buffer[..info.buffer_size()]
            .chunks_exact(channels)
            .map(|c| {
                let rgb = if channels < 3 { [c[0]; 3] } else { [c[0], c[1], c[2]] };
                Vec3::from(rgb.map(|x| f32::from(x) / 255.0))
            })
            .collect();
        Texture::new(info.width as usize, info.height as usize, texels)
    }

    /// The bilinear sample at `uv` (repeating outside 0 to 1).
    pub fn sample(&self, uv: Vec2) -> Vec3 {
        let (w, h) = (self.width as f32, self.height as f32);
        let x = uv.x.rem_euclid(1.0) * w - 0.5;
        let y = (1.0 - uv.y).rem_euclid(1.0) * h - 0.5;
        let (x0, y0) = (x.floor(), y.floor());
        let (fx, fy) = (x - x0, y - y0);
        let at = |i: f32, j: f32| {
            let i = (i as i64).rem_euclid(self.width as i64) as usize;
            let j = (j as i64).rem_euclid(self.height as i64) as usize;
            self.texels[j * self.width + i]
        };
        let top = at(x0, y0).lerp(at(x0 + 1.0, y0), fx);
        let bottom = at(x0, y0 + 1.0).lerp(at(x0 + 1.0, y0 + 1.0), fx);
        top.lerp(bottom, fy)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn samples_repeat_and_v_runs_up_the_image() {
        // Top row red, bottom row blue.
        let (red, blue) = (Vec3::X, Vec3::Z);
        let t = Texture::new(1, 2, vec![red, blue]).unwrap();
        assert!(t.sample(Vec2::new(0.5, 0.75)).distance(red) < 1e-6);
        assert!(t.sample(Vec2::new(0.5, 0.25)).distance(blue) < 1e-6);
        assert!(t.sample(Vec2::new(3.5, 1.75)).distance(red) < 1e-6);
    }
}
