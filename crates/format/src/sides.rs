//! Which sides of a patch may be seen, and the openings of an open surface.
//!
//! A renderer culls the back of a patch only where no eye outside the model can see it. On a
//! closed surface that is everywhere; on an open one (a tube, a scan with holes, a sheet) the
//! back can show through an **opening**: a boundary loop of the source surface. Any line of
//! sight from outside to the back of such a patch crosses a surface spanning one of the loops;
//! spanning surfaces can be chosen inside the loop's convex hull, so inside both the loop's
//! bounding sphere and the slab its points span about a plane; an [`Opening`] records both.
//!
//! A surface whose file wound it inward (or gave each face a twin wound the other way) may
//! be an object or a room seen from inside; the producer winds it outward and marks its
//! patches [`Sides::Both`], and an [`InsideBox`] around it says that their backs show only to
//! an eye inside the box (or through an opening): from outside it they are culled as usual.

use glam::Vec3;

use crate::FormatError;

/// Which sides of a patch an eye outside the model may see (stored per patch, container 1.1).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, Default)]
pub enum Sides {
    /// Only the side its normals face (closed surfaces; what 1.0 files mean). Code 0.
    #[default]
    Front,
    /// The back too, but only through one of the scene's [`Opening`]s: a renderer may cull
    /// it when no opening lies between the eye and the patch. Code 1.
    ThroughOpenings,
    /// Both sides, from anywhere (point clouds, where nothing says what is closed). Code 2.
    Both,
}

impl Sides {
    /// The byte stored in the `SIDE` section.
    pub fn code(self) -> u8 {
        match self {
            Sides::Front => 0,
            Sides::ThroughOpenings => 1,
            Sides::Both => 2,
        }
    }

    /// The value of a stored byte, `None` for an unknown code.
    pub fn from_code(code: u8) -> Option<Sides> {
        match code {
            0 => Some(Sides::Front),
            1 => Some(Sides::ThroughOpenings),
            2 => Some(Sides::Both),
            _ => None,
        }
    }
}

/// One boundary loop of the source surface, relative to the scene offset: a sphere and a
/// slab that both hold every point of the loop (so every surface spanning it inside its
/// convex hull).
///
/// # Guarantees
/// `centre` is finite; `radius` and `half_thickness` are finite and at least 0; `normal` is
/// a unit vector (within 1e-3).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Opening {
    centre: Vec3,
    radius: f32,
    normal: Vec3,
    half_thickness: f32,
}

impl Opening {
    /// An opening: the sphere `(centre, radius)` and the slab of points within
    /// `half_thickness` of the plane through `centre` with unit `normal`. Refuses non-finite
    /// values, negative lengths and a normal that is not unit.
    pub fn new(
        centre: Vec3,
        radius: f32,
        normal: Vec3,
        half_thickness: f32,
    ) -> Result<Opening, FormatError> {
        let length_ok = |v: f32| v.is_finite() && v >= 0.0;
        let unit = normal.is_finite() && (normal.length() - 1.0).abs() <= 1e-3;
        if !centre.is_finite() || !length_ok(radius) || !length_ok(half_thickness) || !unit {
            return Err(FormatError::InvalidOpening);
        }
        Ok(Opening {
            centre,
            radius,
            normal,
            half_thickness,
        })
    }

    /// The unit normal of the slab's plane.
    pub fn normal(&self) -> Vec3 {
        self.normal
    }

    /// Half the slab's thickness (model units).
    pub fn half_thickness(&self) -> f32 {
        self.half_thickness
    }

    /// The centre, relative to the scene offset.
    pub fn centre(&self) -> Vec3 {
        self.centre
    }

    /// The radius (model units).
    pub fn radius(&self) -> f32 {
        self.radius
    }
}

/// The box (relative to the scene offset) holding every surface of a scene whose
/// [`Sides::Both`] patches are wound outward but may be meant to be seen from inside (a room):
/// their backs can show only to an eye inside the box, or, from outside it, through one of
/// the scene's openings as for [`Sides::ThroughOpenings`] (container 1.4, section `INSD`).
///
/// # Guarantees
/// `min` and `max` are finite and `min <= max` on every axis.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct InsideBox {
    min: Vec3,
    max: Vec3,
}

impl InsideBox {
    /// The box from `min` to `max`; refuses non-finite corners and `min > max` on an axis.
    pub fn new(min: Vec3, max: Vec3) -> Result<InsideBox, FormatError> {
        if !min.is_finite() || !max.is_finite() || min.cmpgt(max).any() {
            return Err(FormatError::InvalidInsideBox);
        }
        Ok(InsideBox { min, max })
    }

    /// The lowest corner, relative to the scene offset.
    pub fn min(&self) -> Vec3 {
        self.min
    }

    /// The highest corner, relative to the scene offset.
    pub fn max(&self) -> Vec3 {
        self.max
    }

    /// The smallest box holding both.
    #[must_use]
    pub fn union(&self, other: &InsideBox) -> InsideBox {
        InsideBox {
            min: self.min.min(other.min),
            max: self.max.max(other.max),
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn codes_round_trip_and_unknown_codes_are_refused() {
        for s in [Sides::Front, Sides::ThroughOpenings, Sides::Both] {
            assert_eq!(Sides::from_code(s.code()), Some(s));
        }
        assert_eq!(Sides::from_code(3), None);
    }

    #[test]
    fn inside_boxes_must_be_finite_and_ordered() {
        let b = InsideBox::new(Vec3::ZERO, Vec3::ONE).unwrap();
        assert_eq!((b.min(), b.max()), (Vec3::ZERO, Vec3::ONE));
        let c = InsideBox::new(Vec3::splat(-1.0), Vec3::splat(0.5)).unwrap();
        assert_eq!(b.union(&c).min(), Vec3::splat(-1.0));
        assert_eq!(b.union(&c).max(), Vec3::ONE);
        assert!(InsideBox::new(Vec3::ONE, Vec3::ZERO).is_err());
        assert!(InsideBox::new(Vec3::ZERO, Vec3::new(1.0, f32::NAN, 1.0)).is_err());
        assert!(InsideBox::new(Vec3::splat(f32::NEG_INFINITY), Vec3::ONE).is_err());
    }

    #[test]
    fn openings_must_be_finite_with_a_radius_not_below_zero() {
        let o = |c: Vec3, r: f32, n: Vec3, h: f32| Opening::new(c, r, n, h);
        assert!(o(Vec3::ONE, 0.0, Vec3::Z, 0.0).is_ok());
        assert!(o(Vec3::ONE, -1.0, Vec3::Z, 0.0).is_err());
        assert!(o(Vec3::NAN, 1.0, Vec3::Z, 0.0).is_err());
        assert!(o(Vec3::ONE, f32::INFINITY, Vec3::Z, 0.0).is_err());
        assert!(o(Vec3::ONE, 1.0, Vec3::Z * 2.0, 0.0).is_err());
        assert!(o(Vec3::ONE, 1.0, Vec3::Z, -0.5).is_err());
    }
}
