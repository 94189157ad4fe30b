//! Geometric operators (thesis §4.7.2, after Barr): tapering, a differential scaling
//! r = g(z) = (1 + z)/scale applied to the two coordinates across the axis (eq. 4.6–4.7),
//! and twisting, a differential rotation θ = g(z) = z·scale·π/180 about the axis
//! (eq. 4.8–4.9). The coordinates across the axis are measured from the axis through the
//! input's bounding-box centre; z is the coordinate along the axis, mapped to [-1, 1] over
//! the bounding box when normalised (§4.7.2.1), else taken as it is, then shifted by the
//! step's offset.

use glam::DVec3;

use super::level::BoxFrame;
use super::recipe::{Axis, GeometricParams};

/// The axis coordinate z of `p` as the equations use it.
fn axis_coordinate(p: DVec3, params: &GeometricParams, frame: &BoxFrame) -> f64 {
    let a = params.axis.index();
    let z = if params.normalize { 2.0 * frame.normalise(p)[a] - 1.0 } else { p[a] };
    z - params.offset
}

/// The two axes across `axis`, in right-handed order (x, y for z; y, z for x; z, x for y).
fn across(axis: Axis) -> (usize, usize) {
    match axis {
        Axis::X => (1, 2),
        Axis::Y => (2, 0),
        Axis::Z => (0, 1),
    }
}

/// Tapers `p` (eq. 4.6–4.7): X = r·x, Y = r·y, Z = z with r = (1 + z)/scale.
pub fn taper(p: DVec3, params: &GeometricParams, frame: &BoxFrame) -> DVec3 {
    let r = (1.0 + axis_coordinate(p, params, frame)) / params.scale;
    let (i, j) = across(params.axis);
    let c = frame.centre();
    let mut out = p;
    out[i] = c[i] + r * (p[i] - c[i]);
    out[j] = c[j] + r * (p[j] - c[j]);
    out
}

/// Twists `p` (eq. 4.8–4.9): X = x cos θ − y sin θ, Y = x sin θ + y cos θ, Z = z with
/// θ = z·scale·π/180.
pub fn twist(p: DVec3, params: &GeometricParams, frame: &BoxFrame) -> DVec3 {
    let theta = axis_coordinate(p, params, frame) * params.scale * std::f64::consts::PI / 180.0;
    let (s, co) = theta.sin_cos();
    let (i, j) = across(params.axis);
    let c = frame.centre();
    let (x, y) = (p[i] - c[i], p[j] - c[j]);
    let mut out = p;
    out[i] = c[i] + x * co - y * s;
    out[j] = c[j] + x * s + y * co;
    out
}
