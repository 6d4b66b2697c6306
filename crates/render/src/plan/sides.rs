//! Which backs a frame may cull: the culling mode against a patch's
//! visible sides ([`spatch_format::Sides`]), and for a patch of an open
//! surface, whether an opening can lie between the eye and it.
//!
//! **Portals.** A line of sight from outside the model to the back of an
//! open surface crosses a surface spanning one of its boundary loops,
//! which fits inside the loop's sphere and slab (a portal,
//! [`crate::prepare::portals`]). A portal does not count when the eye and
//! the patch's whole bounding sphere lie on one side of its slab, or the
//! patch lies entirely nearer than it; else the cone from the eye around
//! the portal's sphere is tested against the patch's sphere, as cosines
//! (no inverse trigonometry), leaning to the safe side.
//!
//! **Per frame.** What a portal test needs of the eye alone (the direction
//! and distance to each portal, the angle its sphere spreads, the eye's
//! side of its slab) is computed once per frame ([`PortalsInView`]), so a
//! patch's test is a few products per portal; the portals are tested by
//! groups, whose sphere answers for its members.
//!
//! Cost: per frame, O(portals); per patch of an open surface, one test per
//! group and per member of the groups its line may cross.

use std::sync::LazyLock;

use glam::DVec3;
use spatch_format::Sides;

use crate::options::Culling;
use crate::plan::cull::{spread, COS_SLACK};
use crate::prepare::portals::{Portal, Portals};

/// Extra angle (radians) of the portal test, for the rounding of the
/// stored opening and patch spheres.
pub(crate) const PORTAL_MARGIN: f64 = 1e-3;

/// `sin` and `cos` of [`PORTAL_MARGIN`], computed once.
static PORTAL_MARGIN_SIN_COS: LazyLock<(f64, f64)> = LazyLock::new(|| PORTAL_MARGIN.sin_cos());

/// Whether `culling` lets the back of a patch with `sides` and bounding
/// sphere `(centre, radius)` be culled this frame (its normal cone and
/// cells then face-tested): always under [`Culling::Back`], never under
/// [`Culling::None`]; under [`Culling::Auto`] as the patch's [`Sides`] say,
/// a patch of an open surface only when no opening can lie between the eye
/// and it ([`seen_through_portals`]), and a two-sided one likewise when
/// `outside_box` (the eye is outside the scene's inside box,
/// [`spatch_format::InsideBox`]), else never.
#[inline(always)]
pub(crate) fn back_culled(
    (culling, sides, outside_box): (Culling, Sides, bool),
    portals: &PortalsInView,
    centre: DVec3,
    radius: f64,
) -> bool {
    match (culling, sides) {
        (Culling::Back, _) | (Culling::Auto, Sides::Front) => true,
        (Culling::None, _) => false,
        (Culling::Auto, Sides::Both) if !outside_box => false,
        (Culling::Auto, Sides::ThroughOpenings | Sides::Both) => {
            !seen_through_portals(portals, centre, radius)
        }
    }
}

/// True when a line from the eye to a point of the sphere
/// `(centre, radius)` may cross one of the portals before reaching it
/// (see the module header), group by group.
pub(crate) fn seen_through_portals(portals: &PortalsInView, centre: DVec3, radius: f64) -> bool {
    let Some(sight) = Sight::new(portals.eye, centre, radius) else {
        return true;
    };
    portals.groups.iter().any(|(bound, first, end)| {
        bound.may_cross(&sight)
            && portals.members[*first..*end]
                .iter()
                .any(|p| p.may_cross(&sight))
    })
}

/// The scene's portals as seen from one eye: per portal, what every
/// patch's test reuses.
#[derive(Debug, Clone, Default)]
pub(crate) struct PortalsInView {
    eye: DVec3,
    /// Each member of [`Portals::members`], in its order.
    members: Vec<PortalInView>,
    /// Each group's bound and its members' range.
    groups: Vec<(PortalInView, usize, usize)>,
}

impl PortalsInView {
    /// No portal (a frame of a mesh, or of a scene without openings).
    pub(crate) const NONE: Self = Self {
        eye: DVec3::ZERO,
        members: Vec::new(),
        groups: Vec::new(),
    };

    /// The portals of `portals` seen from `eye`.
    pub(crate) fn new(portals: &Portals, eye: DVec3) -> Self {
        let view = |p: &Portal| PortalInView::new(p, eye);
        Self {
            eye,
            members: portals.members.iter().map(view).collect(),
            groups: portals
                .groups
                .iter()
                .map(|g| (view(&g.bound), g.first, g.end))
                .collect(),
        }
    }
}

/// One portal seen from the eye.
#[derive(Debug, Clone, Copy)]
struct PortalInView {
    portal: Portal,
    to_portal: DVec3,
    distance: f64,
    /// `sin` and `cos` of the angle the portal's sphere spreads.
    spread: (f64, f64),
    /// Signed distance of the eye from the slab's plane.
    eye_side: f64,
}

impl PortalInView {
    fn new(portal: &Portal, eye: DVec3) -> Self {
        let to_portal = portal.centre - eye;
        let distance = to_portal.length();
        Self {
            portal: *portal,
            to_portal,
            distance,
            spread: spread(portal.radius, distance.max(portal.radius)),
            eye_side: (eye - portal.centre).dot(portal.normal),
        }
    }

    /// Whether a line of `sight` may cross the portal before reaching the
    /// patch (see the module header; angles widened by [`PORTAL_MARGIN`]).
    #[inline(always)]
    fn may_cross(&self, sight: &Sight) -> bool {
        let (portal, distance) = (&self.portal, self.distance);
        if distance <= portal.radius {
            return true;
        }
        let (h, eye_side) = (portal.half_thickness, self.eye_side);
        let patch_side = (sight.centre - portal.centre).dot(portal.normal);
        let radius = sight.radius;
        let one_side = (eye_side > h && patch_side - radius > h)
            || (eye_side < -h && patch_side + radius < -h);
        if one_side || sight.distance + radius < distance - portal.radius {
            return false;
        }
        // The angle between the two directions within the two spreads
        // (a, b) and the margin, compared as cosines.
        let ((sin_a, cos_a), (sin_b, cos_b)) = (self.spread, sight.spread);
        let (sin_m, cos_m) = *PORTAL_MARGIN_SIN_COS;
        let (sin_ab, cos_ab) = (sin_a * cos_b + cos_a * sin_b, cos_a * cos_b - sin_a * sin_b);
        // a + b + margin at or past 180°: every angle is within it.
        if cos_ab <= -cos_m {
            return true;
        }
        let cos = sight.to_patch.dot(self.to_portal) / (sight.distance * distance);
        cos >= cos_ab * cos_m - sin_ab * sin_m - COS_SLACK
    }
}

/// A line of sight from the eye to a patch's bounding sphere.
struct Sight {
    centre: DVec3,
    radius: f64,
    to_patch: DVec3,
    distance: f64,
    /// `sin` and `cos` of the angle the patch's sphere spreads.
    spread: (f64, f64),
}

impl Sight {
    /// The sight of the sphere `(centre, radius)` from `eye`; `None` when
    /// the eye lies inside it (every portal may then be in between).
    #[inline(always)]
    fn new(eye: DVec3, centre: DVec3, radius: f64) -> Option<Self> {
        let to_patch = centre - eye;
        let distance = to_patch.length();
        (distance > radius).then(|| Sight {
            centre,
            radius,
            to_patch,
            distance,
            spread: spread(radius, distance),
        })
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::test_rng::XorShift;

    /// The portals of `p` in groups, seen from `eye`.
    fn seen_from(p: &[Portal], eye: DVec3) -> PortalsInView {
        PortalsInView::new(&Portals::grouped(p.to_vec()), eye)
    }

    /// The cosine form decides as the angle form it stands for (`acos` of
    /// the directions' cosine against the sum of the `asin` spreads and
    /// the margin), except within a hair of the boundary.
    #[test]
    fn the_cosine_test_agrees_with_the_angle_form() {
        let mut rng = XorShift(0x2021_cafe);
        let mut unit = move || rng.unit() as f64;
        let mut seen = 0;
        for _ in 0..20_000 {
            let dir = |u: &mut dyn FnMut() -> f64| {
                DVec3::new(u() - 0.5, u() - 0.5, u() - 0.5).normalize_or(DVec3::X)
            };
            let (centre, radius) = (dir(&mut unit) * unit(), 0.05 + unit());
            let eye = dir(&mut unit) * (0.5 + 6.0 * unit());
            // One portal whose slab never separates: only the cone decides.
            let portal = Portal {
                centre: dir(&mut unit) * 2.0,
                radius: 0.05 + 0.5 * unit(),
                normal: dir(&mut unit),
                half_thickness: 1e3,
            };
            let (to_patch, to_portal) = (centre - eye, portal.centre - eye);
            let (dp, dq) = (to_patch.length(), to_portal.length());
            if dp > radius && dq > portal.radius && dp + radius >= dq - portal.radius {
                let cos = (to_patch.dot(to_portal) / (dp * dq)).clamp(-1.0, 1.0);
                let limit = (portal.radius / dq).asin() + (radius / dp).asin() + PORTAL_MARGIN;
                let g = cos.acos() - limit;
                if g.abs() > 1e-9 {
                    let got = seen_through_portals(&seen_from(&[portal], eye), centre, radius);
                    assert_eq!(got, g <= 0.0);
                    seen += got as u32;
                }
            }
        }
        assert!(seen > 500, "{seen}");
    }

    /// Groups change no answer: over random scenes of up to 300 openings
    /// (some large, slabs of any thickness), a patch is seen through the
    /// grouped portals exactly when one of them, tested alone, lets it be.
    #[test]
    fn grouped_portals_answer_as_every_portal_alone() {
        let mut rng = XorShift(0x0bad_5eed);
        let mut unit = move || rng.unit() as f64;
        let (mut seen, mut skipped_groups, mut total) = (0, 0, 0);
        for scene in 0..40 {
            let count = 1 + (scene * 37) % 300;
            let portals: Vec<Portal> = (0..count)
                .map(|_| {
                    let big = unit() < 0.02;
                    Portal {
                        centre: DVec3::new(unit(), unit(), unit()) * 4.0 - 2.0,
                        radius: if big {
                            1.0 + unit()
                        } else {
                            0.01 + 0.1 * unit()
                        },
                        normal: DVec3::new(unit() - 0.5, unit() - 0.5, unit() - 0.5)
                            .normalize_or(DVec3::Z),
                        half_thickness: 0.2 * unit(),
                    }
                })
                .collect();
            for _ in 0..200 {
                let eye = DVec3::new(unit(), unit(), unit()) * 12.0 - 6.0;
                let centre = DVec3::new(unit(), unit(), unit()) * 4.0 - 2.0;
                let radius = 0.01 + 0.2 * unit();
                let grouped = seen_from(&portals, eye);
                let alone = portals
                    .iter()
                    .any(|p| seen_through_portals(&seen_from(&[*p], eye), centre, radius));
                assert_eq!(seen_through_portals(&grouped, centre, radius), alone);
                seen += alone as u32;
                total += 1;
                if let Some(sight) = Sight::new(eye, centre, radius) {
                    let hit = grouped.groups.iter().filter(|g| g.0.may_cross(&sight));
                    skipped_groups += grouped.groups.len() - hit.count();
                }
            }
        }
        // Both answers occur, and groups do skip their members.
        assert!(
            seen > total / 10 && seen < total * 9 / 10,
            "{seen} of {total}"
        );
        assert!(skipped_groups > 10_000, "{skipped_groups}");
    }

    #[test]
    fn a_patch_is_seen_through_a_portal_only_beyond_it_and_in_its_cone() {
        let eye = DVec3::new(0.0, 0.0, 10.0);
        // A thin slab facing the eye.
        let portal = Portal {
            centre: DVec3::ZERO,
            radius: 1.0,
            normal: DVec3::Z,
            half_thickness: 0.1,
        };
        let seen = |c: DVec3, r: f64| seen_through_portals(&seen_from(&[portal], eye), c, r);
        // Behind the opening, in line with it: seen.
        assert!(seen(DVec3::new(0.0, 0.0, -3.0), 0.5));
        // Behind it but far off to the side: not seen.
        assert!(!seen(DVec3::new(8.0, 0.0, -3.0), 0.5));
        // In line but entirely nearer than the opening: not seen through it.
        assert!(!seen(DVec3::new(0.0, 0.0, 5.0), 0.5));
        // Reaching into the opening's cone: seen.
        assert!(seen(DVec3::new(2.0, 0.0, -3.0), 1.5));
        // Eye and patch on the same side of the slab: not through it.
        let side = Portal {
            normal: DVec3::Y,
            ..portal
        };
        let above = seen_from(&[side], DVec3::new(0.0, 5.0, 10.0));
        assert!(!seen_through_portals(
            &above,
            DVec3::new(0.0, 1.0, -3.0),
            0.5
        ));
        assert!(seen_through_portals(
            &above,
            DVec3::new(0.0, -1.0, -3.0),
            0.5
        ));
        // No portal at all: never; the eye inside the opening: always.
        assert!(!seen_through_portals(
            &seen_from(&[], eye),
            DVec3::ZERO,
            1.0
        ));
        let inside = seen_from(&[portal], DVec3::new(0.0, 0.5, 0.0));
        assert!(seen_through_portals(
            &inside,
            DVec3::new(9.0, 0.0, 0.0),
            0.1
        ));
    }
}
