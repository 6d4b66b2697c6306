//! The scene's openings as portals, grouped so that a frame tests few of
//! them per patch.
//!
//! Automatic culling asks, for every patch whose back could be culled,
//! whether a line from the eye to it may cross an opening
//! ([`crate::plan::sides::seen_through_portals`]). Tested one by one, that
//! is patches × openings portal tests a frame: a raw range scan (3,676
//! patches, 237 openings) spent about half of its planning on them. Two
//! things here cut it, neither changing an answer (the third, the
//! per-eye values once per frame, is [`crate::plan::sides`]'s):
//!
//! - **Groups.** Portals that lie near each other (consecutive in the
//!   Morton order of their centres) form groups of [`GROUP_SIZE`], each
//!   with a sphere holding its members' spheres. A line that crosses a
//!   member's sphere crosses the group's, and the group's cone from the eye
//!   holds each member's, so when the group's test (the same test, without
//!   a slab) says no, every member's says no: the members are skipped.
//! - **Largest first.** Within a group, and between groups, the larger
//!   spheres come first: a scan's outer rim, through which nearly every
//!   patch may be seen from behind, answers yes at the first test.
//!
//! Input: the scene's openings ([`spatch_format::Opening`]) and its
//! offset. Cost: a sort of the openings, once per scene.

use glam::DVec3;
use spatch_format::Opening;

/// An opening of the scene's surface in model space: a sphere and a slab
/// holding one boundary loop ([`spatch_format::Opening`]), or, for a
/// group's bound, a sphere only (`half_thickness` infinite).
#[derive(Debug, Clone, Copy, PartialEq)]
pub(crate) struct Portal {
    pub(crate) centre: DVec3,
    pub(crate) radius: f64,
    /// Unit normal of the slab's plane (through `centre`).
    pub(crate) normal: DVec3,
    pub(crate) half_thickness: f64,
}

/// Members per group. Why 8: a scan's 237 openings become 30 group tests
/// and the members of the groups they hit; groups of 4 and 16 were
/// measured too (docs/algorithms/render.md, "Open surfaces").
pub(crate) const GROUP_SIZE: usize = 8;

/// A group of neighbouring portals: the sphere holding them and where
/// they lie in [`Portals::members`].
#[derive(Debug, Clone, Copy, PartialEq)]
pub(crate) struct PortalGroup {
    /// The group's sphere as a portal without a slab.
    pub(crate) bound: Portal,
    /// First member in [`Portals::members`].
    pub(crate) first: usize,
    /// One past the last member.
    pub(crate) end: usize,
}

/// The scene's portals in groups (see the module header).
#[derive(Debug, Clone, Default, PartialEq)]
pub(crate) struct Portals {
    /// Every portal, each group's members together, larger spheres first.
    pub(crate) members: Vec<Portal>,
    /// The groups, larger spheres first.
    pub(crate) groups: Vec<PortalGroup>,
}

impl Portals {
    /// The portals of `openings` (relative to `offset`) in groups.
    pub(crate) fn new(openings: &[Opening], offset: DVec3) -> Self {
        let portals: Vec<Portal> = openings
            .iter()
            .map(|o| Portal {
                centre: offset + o.centre().as_dvec3(),
                radius: f64::from(o.radius()),
                normal: o.normal().as_dvec3(),
                half_thickness: f64::from(o.half_thickness()),
            })
            .collect();
        Self::grouped(portals)
    }

    /// Groups `portals` (see the module header).
    pub(crate) fn grouped(mut portals: Vec<Portal>) -> Self {
        sort_by_morton_code(&mut portals);
        let mut runs: Vec<Vec<Portal>> = portals
            .chunks(GROUP_SIZE)
            .map(|run| {
                let mut run = run.to_vec();
                run.sort_by(|a, b| b.radius.total_cmp(&a.radius));
                run
            })
            .collect();
        runs.sort_by(|a, b| {
            bounding_sphere(b)
                .radius
                .total_cmp(&bounding_sphere(a).radius)
        });
        let mut set = Self::default();
        for run in runs {
            let first = set.members.len();
            set.members.extend_from_slice(&run);
            set.groups.push(PortalGroup {
                bound: bounding_sphere(&run),
                first,
                end: set.members.len(),
            });
        }
        set
    }
}

/// Sorts `portals` along the Morton order of their centres in the cube
/// around the centres' box (10 bits per axis), so that a run of them lies
/// close together.
fn sort_by_morton_code(portals: &mut [Portal]) {
    let Some(first) = portals.first() else {
        return;
    };
    let (lo, hi) = portals
        .iter()
        .fold((first.centre, first.centre), |(lo, hi), p| {
            (lo.min(p.centre), hi.max(p.centre))
        });
    let scale = 1023.0 / (hi - lo).max_element().max(f64::MIN_POSITIVE);
    let code = |p: &Portal| {
        let q = ((p.centre - lo) * scale).round().as_uvec3();
        spread_bits(q.x) | spread_bits(q.y) << 1 | spread_bits(q.z) << 2
    };
    portals.sort_by_cached_key(code);
}

/// The low 10 bits of `v` moved to every third bit.
fn spread_bits(v: u32) -> u32 {
    let mut x = v & 0x3ff;
    x = (x | x << 16) & 0x0300_00ff;
    x = (x | x << 8) & 0x0300_f00f;
    x = (x | x << 4) & 0x030c_30c3;
    (x | x << 2) & 0x0924_9249
}

/// The sphere holding every sphere of `run` (its box's centre and the
/// farthest reach from it), grown by a relative 1e-9 so that rounding in
/// the tests never makes it smaller than a member's; no slab.
fn bounding_sphere(run: &[Portal]) -> Portal {
    let reach = |p: &Portal| {
        (
            p.centre - DVec3::splat(p.radius),
            p.centre + DVec3::splat(p.radius),
        )
    };
    let (lo, hi) = run.iter().map(reach).fold(
        (DVec3::INFINITY, DVec3::NEG_INFINITY),
        |(lo, hi), (a, b)| (lo.min(a), hi.max(b)),
    );
    let centre = (lo + hi) * 0.5;
    let radius = run
        .iter()
        .map(|p| (p.centre - centre).length() + p.radius)
        .fold(0.0, f64::max);
    Portal {
        centre,
        radius: radius * (1.0 + 1e-9) + 1e-12,
        normal: DVec3::Z,
        half_thickness: f64::INFINITY,
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn portal(x: f64, y: f64, z: f64, radius: f64) -> Portal {
        Portal {
            centre: DVec3::new(x, y, z),
            radius,
            normal: DVec3::Y,
            half_thickness: 0.01,
        }
    }

    #[test]
    fn groups_hold_their_members_largest_first() {
        // A rim of radius 5 among 40 small holes on a line.
        let mut portals: Vec<Portal> = (0..40)
            .map(|k| portal(k as f64, 0.0, (k % 3) as f64, 0.1 + 0.01 * k as f64))
            .collect();
        portals.push(portal(20.0, 0.0, 0.0, 5.0));
        let set = Portals::grouped(portals.clone());
        assert_eq!(set.members.len(), 41);
        assert_eq!(set.groups.len(), 41usize.div_ceil(GROUP_SIZE));
        // Every portal once.
        for p in &portals {
            assert_eq!(set.members.iter().filter(|m| *m == p).count(), 1);
        }
        // The rim's group comes first, the rim first in it.
        assert_eq!(set.members[0].radius, 5.0);
        let mut last = f64::INFINITY;
        for g in &set.groups {
            assert!(g.bound.radius <= last);
            last = g.bound.radius;
            let members = &set.members[g.first..g.end];
            assert!(members.windows(2).all(|w| w[0].radius >= w[1].radius));
            for m in members {
                let reach = (m.centre - g.bound.centre).length() + m.radius;
                assert!(reach < g.bound.radius, "{reach} {:?}", g.bound);
            }
            assert!(g.bound.half_thickness.is_infinite());
        }
        // Groups of neighbours: the 40 small holes span 39 units, a group
        // of eight of them far less.
        let small = set.groups.iter().filter(|g| g.bound.radius < 5.0);
        assert!(small.into_iter().all(|g| g.bound.radius < 8.0));
    }

    #[test]
    fn no_opening_gives_no_group() {
        let set = Portals::new(&[], DVec3::ZERO);
        assert!(set.members.is_empty());
        assert!(set.groups.is_empty());
    }
}
