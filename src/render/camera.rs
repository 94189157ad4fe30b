//! The camera: a perspective view orbiting the mesh's bounding sphere, fitted so the whole
//! mesh fills the frame at any yaw and pitch.

use glam::{DVec3, Vec3};

/// Which world axis points up in the picture.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default, serde::Serialize, serde::Deserialize)]
#[cfg_attr(feature = "cli", derive(clap::ValueEnum))]
#[serde(rename_all = "lowercase")]
pub enum UpAxis {
    /// +X up.
    X,
    /// +Y up (the usual convention of scanned meshes).
    Y,
    /// +Z up (terrains).
    #[default]
    Z,
}

impl UpAxis {
    /// The unit vector of the axis.
    pub(crate) fn vector(self) -> DVec3 {
        match self {
            UpAxis::X => DVec3::X,
            UpAxis::Y => DVec3::Y,
            UpAxis::Z => DVec3::Z,
        }
    }
}

/// A fitted perspective camera. Projected points are `(x, y)` in pixels (y down) and the
/// inverse view depth `1/z`, which interpolates linearly across a projected triangle.
#[derive(Debug, Clone, Copy)]
pub struct Camera {
    eye: DVec3,
    right: DVec3,
    up: DVec3,
    forward: DVec3,
    focal: f64,
    centre: (f64, f64),
}

/// Vertical field of view: narrow, so that shapes read almost orthographically.
const FIELD_OF_VIEW_DEG: f64 = 25.0;

impl Camera {
    /// A camera looking at the sphere around `bbox`, `yaw` degrees around the up axis
    /// (0 = looking along +Y for Z up) and `pitch` degrees above the horizon, for an image
    /// of `width` × `height` pixels with a margin of 4 %.
    pub fn fit(
        bbox: (DVec3, DVec3),
        up_axis: UpAxis,
        yaw_deg: f64,
        pitch_deg: f64,
        width: usize,
        height: usize,
    ) -> Self {
        let (lo, hi) = bbox;
        let target = (lo + hi) * 0.5;
        let radius = ((hi - lo).length() * 0.5).max(1e-12);
        let up_world = up_axis.vector();
        // A horizontal frame (a, b) perpendicular to the up axis, right-handed with it.
        let a = up_world.any_orthonormal_vector();
        let (a, b) = match up_axis {
            UpAxis::Z => (DVec3::X, DVec3::Y),
            UpAxis::Y => (DVec3::Z, DVec3::X),
            UpAxis::X => (a, up_world.cross(a)),
        };
        let (yaw, pitch) = (yaw_deg.to_radians(), pitch_deg.clamp(-89.0, 89.0).to_radians());
        // Direction from the target to the eye.
        let horizontal = -(b * yaw.cos()) + a * yaw.sin();
        let back = horizontal * pitch.cos() + up_world * pitch.sin();
        let half = (FIELD_OF_VIEW_DEG.to_radians() * 0.5).tan();
        let aspect_fit = if width >= height { 1.0 } else { width as f64 / height as f64 };
        let distance = radius / (half * aspect_fit * 0.96).atan().sin();
        let eye = target + back * distance;
        let forward = -back;
        let right = forward.cross(up_world).try_normalize().unwrap_or(a);
        let up = right.cross(forward);
        let focal = height as f64 * 0.5 / half;
        Camera { eye, right, up, forward, focal, centre: (width as f64 * 0.5, height as f64 * 0.5) }
    }

    /// The same view zoomed and shifted so that the projected `points` fill the frame
    /// (`width` × `height` pixels) up to a margin of 4 % on the tighter side.
    pub fn framed(&self, points: &[Option<Vec3>], width: usize, height: usize) -> Camera {
        let (mut lo, mut hi) = (glam::Vec2::splat(f32::INFINITY), glam::Vec2::splat(f32::NEG_INFINITY));
        for p in points.iter().flatten() {
            lo = lo.min(p.truncate());
            hi = hi.max(p.truncate());
        }
        let extent = (hi - lo).as_dvec2();
        if !(extent.x > 0.0 || extent.y > 0.0) || !extent.is_finite() {
            return *self;
        }
        let zoom = (0.92 * width as f64 / extent.x.max(1e-9)).min(0.92 * height as f64 / extent.y.max(1e-9));
        let middle = ((lo + hi) * 0.5).as_dvec2();
        let (cx, cy) = self.centre;
        Camera {
            focal: self.focal * zoom,
            centre: (width as f64 * 0.5 - (middle.x - cx) * zoom, height as f64 * 0.5 - (middle.y - cy) * zoom),
            ..*self
        }
    }

    /// Pixel coordinates and inverse depth of `p`; `None` behind the eye.
    pub fn project(&self, p: DVec3) -> Option<Vec3> {
        let d = p - self.eye;
        let z = d.dot(self.forward);
        if z <= 1e-9 {
            return None;
        }
        let x = self.centre.0 + self.focal * d.dot(self.right) / z;
        let y = self.centre.1 - self.focal * d.dot(self.up) / z;
        Some(Vec3::new(x as f32, y as f32, (1.0 / z) as f32))
    }

    /// The eye and the (unnormalised) direction through pixel position (x, y), scaled so
    /// that `eye + t·direction` lies at view depth t.
    pub fn ray(&self, x: f64, y: f64) -> (DVec3, DVec3) {
        let (cx, cy) = self.centre;
        (self.eye, self.forward + self.right * ((x - cx) / self.focal) - self.up * ((y - cy) / self.focal))
    }

    /// A world direction expressed in the camera frame (x right, y up, z towards the eye).
    pub fn to_view(&self, direction: DVec3) -> Vec3 {
        Vec3::new(direction.dot(self.right) as f32, direction.dot(self.up) as f32, -direction.dot(self.forward) as f32)
    }

    /// The direction from the eye to `p`, in the camera frame.
    pub fn view_ray(&self, p: DVec3) -> Vec3 {
        self.to_view((p - self.eye).normalize_or_zero())
    }
}
