//! The pinhole camera of every picture: its frame, its pixel rays, its default framing.

use crate::error::{Error, ErrorKind, Result};
use crate::geom::DVec3;
use crate::math;
use crate::scene::Scene3;

/// The camera frame `(right, up, forward)` looking along `forward` (need not be unit):
/// up is `+y`, or `+z` when `forward` is within about 8° of the `y` axis
/// (`|forward_y| > 0.99`); `right = forward × up_world`, `up = right × forward`. `None` for
/// a zero or non-finite direction. The one camera frame of the crate (pictures, the
/// viewpoint rasteriser).
pub(crate) fn look_basis(forward: DVec3) -> Option<(DVec3, DVec3, DVec3)> {
    let forward = forward.try_normalize()?;
    let world_up = if forward.y.abs() > 0.99 {
        DVec3::Z
    } else {
        DVec3::Y
    };
    let right = forward.cross(world_up).try_normalize()?;
    let up = right.cross(forward);
    Some((right, up, forward))
}

/// A pinhole camera: eye, look-at point, vertical field of view and image size, with its
/// frame (`look_basis`: up is `+y`, or `+z` when looking along `y`) and the image plane at
/// distance 1 spanning `2 tan(fov/2)` vertically and `2 tan(fov/2) W/H` across. The ray of
/// position `(u, v) ∈ [0, 1)²` in pixel `(x, y)` (rows from the top):
///
/// ```text
/// d = f + r · (2 (x + u)/W − 1) tan(fov/2) W/H + u⃗ · (1 − 2 (y + v)/H) tan(fov/2)
/// ```
///
/// (`f, r, u⃗` the forward, right and up unit vectors; pixel centres at `u = v = ½`).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Camera3 {
    eye: DVec3,
    look: DVec3,
    fov_degrees: f64,
    width: u32,
    height: u32,
    right: DVec3,
    up: DVec3,
    forward: DVec3,
    tan_half: f64,
}

impl Camera3 {
    /// Largest image side in pixels.
    pub const MAX_SIDE: u32 = 8192;

    /// A camera at `eye` looking at `look`, vertical field of view `fov_degrees`, image
    /// `width × height` pixels.
    ///
    /// # Errors
    /// [`ErrorKind::BadParameter`] for a field of view outside `(0, 180)` degrees, a zero
    /// image side, non-finite points or `eye = look`; [`ErrorKind::TooLarge`] for a side
    /// above [`Camera3::MAX_SIDE`].
    pub fn new(
        eye: DVec3,
        look: DVec3,
        fov_degrees: f64,
        (width, height): (u32, u32),
    ) -> Result<Self> {
        let bad = |name, value| Err(Error::new(ErrorKind::BadParameter { name, value }));
        if !(fov_degrees > 0.0 && fov_degrees < 180.0) {
            return bad("field of view (degrees)", fov_degrees);
        }
        if width == 0 || height == 0 {
            return bad("image side", f64::from(width.min(height)));
        }
        if width > Self::MAX_SIDE || height > Self::MAX_SIDE {
            return Err(Error::new(ErrorKind::TooLarge {
                what: "image side",
                max: u64::from(Self::MAX_SIDE),
            }));
        }
        if !(eye.is_finite() && look.is_finite()) {
            return bad("camera position", f64::NAN);
        }
        if (look - eye).try_normalize().is_none() {
            return bad("distance from eye to look", (look - eye).length());
        }
        let Some((right, up, forward)) = look_basis(look - eye) else {
            return bad("camera direction", f64::NAN);
        };
        Ok(Self {
            eye,
            look,
            fov_degrees,
            width,
            height,
            right,
            up,
            forward,
            tan_half: math::tan(fov_degrees.to_radians() * 0.5),
        })
    }

    /// The camera that frames the box `bounds`: looking at its centre along `+z` from where
    /// its bounding sphere, times 0.85, fills the field of view — into a room whose open
    /// side faces `−z`, like the Cornell box's (the default view of `refine --png`,
    /// `render` and the chapter 6 pictures).
    ///
    /// # Errors
    /// As [`Camera3::new`].
    pub fn framing(bounds: (DVec3, DVec3), fov_degrees: f64, size: (u32, u32)) -> Result<Self> {
        let (lo, hi) = bounds;
        let centre = (lo + hi) * 0.5;
        let radius = (hi - lo).length() * 0.5;
        let half = (fov_degrees.to_radians() * 0.5).clamp(1e-6, 1.5);
        let distance = (radius / math::sin(half) * 0.85).max(1e-9);
        Self::new(centre - DVec3::Z * distance, centre, fov_degrees, size)
    }

    /// The camera with `eye` and `look` given in the scene's own units (as written in its
    /// file), converted to its stored frame.
    ///
    /// # Errors
    /// As [`Camera3::new`].
    pub fn in_scene_units(
        scene: &Scene3,
        eye: DVec3,
        look: DVec3,
        fov_degrees: f64,
        size: (u32, u32),
    ) -> Result<Self> {
        let f = scene.frame();
        Self::new(f.to_stored(eye), f.to_stored(look), fov_degrees, size)
    }

    /// The eye.
    #[must_use]
    pub fn eye(&self) -> DVec3 {
        self.eye
    }

    /// The point looked at.
    #[must_use]
    pub fn look(&self) -> DVec3 {
        self.look
    }

    /// The vertical field of view, degrees.
    #[must_use]
    pub fn fov_degrees(&self) -> f64 {
        self.fov_degrees
    }

    /// Image width and height in pixels.
    #[must_use]
    pub fn size(&self) -> (u32, u32) {
        (self.width, self.height)
    }

    /// The (unnormalised) direction through position `uv ∈ [0, 1)²` of pixel `(px, py)`,
    /// rows from the top (the type's docs).
    #[must_use]
    pub fn direction(&self, px: u32, py: u32, uv: [f64; 2]) -> DVec3 {
        let (w, h) = (f64::from(self.width), f64::from(self.height));
        let aspect = w / h;
        let sx = (2.0 * (f64::from(px) + uv[0]) / w - 1.0) * self.tan_half * aspect;
        let sy = (1.0 - 2.0 * (f64::from(py) + uv[1]) / h) * self.tan_half;
        self.forward + self.right * sx + self.up * sy
    }

    /// `p` in the camera's frame: `(right, up, forward)` coordinates relative to the eye.
    pub(crate) fn in_camera_frame(&self, p: DVec3) -> DVec3 {
        let d = p - self.eye;
        DVec3::new(d.dot(self.right), d.dot(self.up), d.dot(self.forward))
    }

    /// A direction in the camera's frame.
    pub(crate) fn direction_to_camera(&self, d: DVec3) -> DVec3 {
        DVec3::new(d.dot(self.right), d.dot(self.up), d.dot(self.forward))
    }

    /// The window of the image plane at distance 1: half its width and half its height,
    /// `(tan(fov/2) W/H, tan(fov/2))`.
    pub(crate) fn half_window(&self) -> (f64, f64) {
        let aspect = f64::from(self.width) / f64::from(self.height);
        (self.tan_half * aspect, self.tan_half)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_centre_ray_looks_forward_and_bad_cameras_are_refused() {
        let v = DVec3::new;
        let c = Camera3::new(v(0., 0., -3.), DVec3::ZERO, 90.0, (4, 2)).unwrap();
        // 4 × 2 pixels: the centre is the corner of pixels (1, 0) and (2, 1)
        let d = c.direction(2, 1, [0.0, 0.0]);
        assert!((d - DVec3::Z).length() < 1e-15, "{d}");
        // The right edge of the image at 90°: tan 45° · W/H = 2 to the right (−x here: +z
        // forward, +y up, right = z × y = −x)
        let d = c.direction(3, 1, [1.0, 0.0]);
        assert!((d - v(-2.0, 0.0, 1.0)).length() < 1e-15, "{d}");
        assert_eq!(c.in_camera_frame(DVec3::ZERO), v(0., 0., 3.));
        for bad in [
            Camera3::new(v(0., 0., -3.), DVec3::ZERO, 180.0, (4, 2)),
            Camera3::new(v(0., 0., -3.), DVec3::ZERO, 40.0, (0, 2)),
            Camera3::new(
                v(0., 0., -3.),
                DVec3::ZERO,
                40.0,
                (Camera3::MAX_SIDE + 1, 2),
            ),
            Camera3::new(DVec3::ZERO, DVec3::ZERO, 40.0, (4, 2)),
            Camera3::new(v(f64::NAN, 0., 0.), DVec3::ZERO, 40.0, (4, 2)),
        ] {
            assert!(bad.is_err(), "{bad:?}");
        }
        // Looking straight down: up is +z
        let down = Camera3::new(v(0., 5., 0.), DVec3::ZERO, 40.0, (4, 4)).unwrap();
        assert_eq!(down.up, DVec3::Z);
    }
}
