//! Tests of [`crate::prepare::patch`].

use crate::isa::Isa;
use crate::prepare::level_shading::LevelShading;
use crate::prepare::normal_buffer::NormalBuffer;
use crate::prepare::normal_buffer::SlotSet;
use crate::prepare::normals::node_differences;
use crate::prepare::patch::*;
use crate::prepare::scene::PreparedScene;
use glam::{DVec3, Vec3};
use spatch_format::{ColourChannel, Frame, GridSize, Patch, Scene, EMPTY};

/// Checks every level of `p`: each filled node's prepared normal is the
/// normal buffer's (bit for bit, as a projected node carries it), each
/// empty node's is zero, and the slot set is that of the used nodes'
/// slots. Returns the filled nodes checked.
fn check_levels(p: &PreparedPatch, buffer: &mut NormalBuffer) -> usize {
    let mut checked = 0;
    for m in 0..p.level_count() {
        let level = p.level(m);
        // Both ways of finding the slot set: with the shading inputs
        // (even levels) and on its own (odd levels).
        let shading = match m % 2 {
            0 => p.counted_shading(m),
            _ => p.shading(m),
        };
        let (cols, rows, d) = (level.cols, level.rows, &level.displacements);
        for j in 0..rows {
            for i in 0..cols {
                let k = j * cols + i;
                let got = shading.normals[k].to_array().map(|v| v.to_bits() as i32);
                if d[k] == EMPTY {
                    assert_eq!(got, [0; 4], "empty node {i}, {j} of level {m}");
                    continue;
                }
                let (gi, gj) = node_differences(d, cols, rows, i, j, EMPTY);
                let n = buffer.normal(m, p.ratios_at(m), gi, gj);
                let bits = n.to_array().map(crate::fixed::attr_to_bits);
                assert_eq!(got[..3], bits, "node {i}, {j} of level {m}");
                assert_eq!(got[3], 0);
                checked += 1;
            }
        }
        let used = level.used.iter().zip(level.normal_slots());
        let expected = SlotSet::new(used.filter(|&(&u, _)| u).map(|(_, &s)| s));
        assert_eq!(*p.slot_set(m), expected, "level {m}");
    }
    checked
}

/// A patch of `cols × rows` nodes with displacements `d` (row-major) and
/// `colours`, on the unit axes with `z` units a code.
fn grid_patch([cols, rows]: [u32; 2], d: Vec<u16>, z: f32, colours: Option<Vec<[u8; 4]>>) -> Patch {
    let frame = Frame::new(Vec3::ZERO, Vec3::X, Vec3::Y, Vec3::Z * z).unwrap();
    Patch::new(frame, GridSize::new(cols, rows).unwrap(), d, colours).unwrap()
}

#[test]
fn prepared_normals_are_the_normals_nodes_carried() {
    let options = spatch_sphere::SphereOptions::default();
    let scene = spatch_sphere::build_sphere(&options).unwrap().scene;
    let prepared = PreparedScene::new(&scene);
    let mut buffer = NormalBuffer::default();
    let checked: usize = (prepared.patches.iter().step_by(97))
        .map(|p| check_levels(p, &mut buffer))
        .sum();
    assert!(checked > 1000, "{checked}");
}

/// Level 0 built with the cone's displacement range is the level built
/// on its own (which finds the range from its used nodes).
fn check_level_zero(p: &PreparedPatch, patch: &Patch) {
    let own = crate::prepare::mip::base_level(patch).expect("drawable");
    let built = p.level(0);
    assert_eq!(built.d_range, own.d_range);
    assert_eq!(built.weights(), own.weights());
    assert_eq!(built.cell_flags, own.cell_flags);
    assert_eq!(built.used, own.used);
}

#[test]
fn prepared_normals_hold_on_grids_with_holes_and_steep_steps() {
    // Grids of 2–20 nodes a side (some a multiple of four, some not),
    // empty nodes from none to most, steps small (in the normal
    // buffer's table) and large (outside it), ratios of a scan.
    let mut rng = crate::test_rng::XorShift(0x5eed_0a11);
    let mut buffer = NormalBuffer::default();
    let mut checked = 0;
    for case in 0..300 {
        let (cols, rows) = (2 + rng.below(19), 2 + rng.below(19));
        let holes = [0, 5, 30, 70][case % 4];
        let step = [2, 20, 200][case % 3];
        let d = rng.holed_grid((cols * rows) as usize, holes, 1000, step);
        let z = 0.002 + rng.unit() * 0.05;
        let patch = grid_patch([cols, rows], d, z, None);
        let scene = Scene::new(DVec3::ZERO, ColourChannel::None, vec![patch]).unwrap();
        for p in &PreparedScene::new(&scene).patches {
            checked += check_levels(p, &mut buffer);
            check_level_zero(p, &scene.patches()[0]);
        }
    }
    assert!(checked > 10_000, "{checked}");
}

#[test]
fn level_one_by_quarters_shades_with_level_zero_normals_at_shared_nodes() {
    // Noisy grids with holes: each filled node (i, j) of level 1 drawn
    // by quarters carries level 0's normal of node (2i, 2j) when that
    // one is filled, else level 1's own; and the two differ on these
    // grids (the noise level 1 averages), so the test sees the choice.
    let mut rng = crate::test_rng::XorShift(0x0a1e_5ade);
    let (mut shared, mut differing) = (0, 0);
    for case in 0..120 {
        let (cols, rows) = (3 + rng.below(18), 3 + rng.below(18));
        let d = rng.holed_grid((cols * rows) as usize, [0, 5, 30][case % 3], 500, 40);
        let patch = grid_patch([cols, rows], d, 0.01, None);
        let isa = Isa::detect(true);
        let Some(p) = PreparedPatch::new(&patch, DVec3::ZERO, isa) else {
            continue;
        };
        if p.level_count() < 2 {
            continue;
        }
        let (coarse, fine) = (p.level(QUARTERED_ONE), p.level(0));
        let own = LevelShading::with_isa(isa, coarse, p.ratios_at(1), None);
        let (got, fine_normals) = (&p.shading(QUARTERED_ONE).normals, &p.shading(0).normals);
        for j in 0..coarse.rows {
            for i in 0..coarse.cols {
                let k = j * coarse.cols + i;
                let f = (2 * i < fine.cols && 2 * j < fine.rows)
                    .then(|| 2 * j * fine.cols + 2 * i)
                    .filter(|&f| fine.displacements[f] != EMPTY);
                match f {
                    Some(f) if coarse.displacements[k] != EMPTY => {
                        assert_eq!(got[k], fine_normals[f], "case {case}, node {i}, {j}");
                        shared += 1;
                        differing += usize::from(own.normals[k] != fine_normals[f]);
                    }
                    _ => assert_eq!(got[k], own.normals[k], "case {case}, node {i}, {j}"),
                }
            }
        }
    }
    assert!(
        shared > 2000 && differing > shared / 2,
        "{shared}, {differing}"
    );
}

#[test]
fn level_one_from_the_nodes_is_level_zero_halved() {
    // Level 1 built before level 0 (from the patch's nodes) and after
    // it (halving level 0) are the same level, on grids with holes and
    // colours; level 0 built afterwards is level 0 built first.
    let mut rng = crate::test_rng::XorShift(0x1e7e_1011);
    let mut compared = 0;
    for case in 0..200 {
        let (cols, rows) = (3 + rng.below(18), 3 + rng.below(18));
        let holes = [0, 5, 30][case % 3];
        let d = rng.holed_grid((cols * rows) as usize, holes, 500, 60);
        let colours = (case % 2 == 0).then(|| {
            (0..cols * rows)
                .map(|_| [rng.below(256) as u8, rng.below(256) as u8, 90, 255])
                .collect::<Vec<_>>()
        });
        let patch = grid_patch([cols, rows], d, 0.01, colours);
        let isa = Isa::detect(true);
        let (Some(first), Some(second)) = (
            PreparedPatch::new(&patch, DVec3::ZERO, isa),
            PreparedPatch::new(&patch, DVec3::ZERO, isa),
        ) else {
            continue;
        };
        if first.level_count() < 2 {
            continue;
        }
        let (direct, zero_after) = (first.level(1), first.level(0));
        let (zero, halved) = (second.level(0), second.level(1));
        assert_eq!(direct.displacements, halved.displacements, "case {case}");
        assert_eq!(direct.colours, halved.colours, "case {case}");
        assert_eq!(direct.cell_flags, halved.cell_flags, "case {case}");
        assert_eq!(direct.used, halved.used, "case {case}");
        assert_eq!(direct.d_range, halved.d_range, "case {case}");
        assert_eq!(direct.spacing, halved.spacing, "case {case}");
        assert_eq!(zero_after.displacements, zero.displacements, "case {case}");
        assert_eq!(zero_after.cell_flags, zero.cell_flags, "case {case}");
        compared += 1;
    }
    assert!(compared > 100, "{compared}");
}
