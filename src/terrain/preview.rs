//! A heightfield terrain's picture: a hillshaded colour map, one pixel per grid point, or
//! for a streamed terrain every k-th point of the streamed rows.

use crate::error::{Error, Result};
use crate::render::Picture;
use crate::render::hillshade::{Relief, hillshade};
use crate::terrain::{Heightfield, Rect, TerrainParams, heights};

/// The largest side of a streamed terrain's preview, pixels: every k-th point of every
/// k-th streamed row, k the smallest stride that fits.
const STREAMED_PREVIEW_SIDE: usize = 1024;

/// The hillshaded colour map of `heights` (rows of `columns` points, every `stride`-th
/// point of `params`' grid).
pub fn relief_picture(params: &TerrainParams, heights: &[f64], columns: usize, stride: u64) -> Picture {
    let last = (params.size - 1).max(1) as f64;
    let k = stride as f64;
    let relief =
        Relief { heights, columns, spacing: (params.width / last * k, params.depth / last * k), exaggeration: None };
    hillshade(&relief, |h| params.color(h))
}

/// A streamed terrain's preview, gathered from the rows as they stream past: the heights
/// at every `stride`-th point of every `stride`-th row.
pub struct PreviewSampler {
    rect: Rect,
    stride: u64,
    columns: usize,
    heights: Vec<f64>,
}

impl PreviewSampler {
    /// A sampler of `rect` at the smallest stride that fits 1024 pixels a side.
    pub fn new(rect: Rect) -> Self {
        let side = rect.width().max(rect.height());
        let stride = side.div_ceil(STREAMED_PREVIEW_SIDE).max(1) as u64;
        let columns = (rect.width() as u64).div_ceil(stride) as usize;
        let rows = (rect.height() as u64).div_ceil(stride) as usize;
        PreviewSampler { rect, stride, columns, heights: Vec::with_capacity(columns * rows) }
    }

    /// Takes the sampled points of rows y0..=y1 of `field`.
    pub fn take(&mut self, field: &Heightfield, y0: u64, y1: u64) {
        for y in (y0..=y1).filter(|y| (y - self.rect.y0).is_multiple_of(self.stride)) {
            self.heights.extend((0..self.columns as u64).map(|i| field.at(self.rect.x0 + i * self.stride, y)));
        }
    }

    /// The hillshaded picture, one pixel per sampled point.
    pub fn picture(&self, params: &TerrainParams) -> Picture {
        relief_picture(params, &self.heights, self.columns, self.stride)
    }
}

/// The largest grid a preview pictures (one pixel per point).
const PREVIEW_MAX_SIDE: usize = 8193;

/// A hillshaded colour map of the heights on `rect`, one pixel per grid point.
///
/// # Errors
/// [`Error::InvalidInput`] for a region over 8193 points a side; the generator's
/// errors.
pub fn preview(params: &TerrainParams, rect: Rect) -> Result<Picture> {
    if rect.width() > PREVIEW_MAX_SIDE || rect.height() > PREVIEW_MAX_SIDE {
        return Err(Error::InvalidInput(format!(
            "--preview pictures at most {PREVIEW_MAX_SIDE}x{PREVIEW_MAX_SIDE} points, one pixel each: preview a tile instead"
        )));
    }
    let field = heights(params, rect)?;
    Ok(relief_picture(params, &field.heights, rect.width(), 1))
}
