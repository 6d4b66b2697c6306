//! Tests of [`crate::plan::portal_cells`]: the screen boxes hold what they
//! bound, and a patch behind a portal keeps exactly the cells facing away
//! inside the portal's region.

use glam::{DVec3, Mat3, Vec3};
use spatch_format::{Frame, GridSize, Patch};

use crate::camera::{Camera, View};
use crate::fixed::XY_ONE;
use crate::grid::CELL_DRAW;
use crate::plan::measure::measure_cells;
use crate::plan::node_xy::NodeXY;
use crate::plan::portal_cells::{
    boxes_touch, local_box_touches, portal_box, sphere_bounds, ScreenBox,
};
use crate::plan::project::{project_nodes_exact, Projector};
use crate::plan::split::NodeRange;
use crate::prepare::scene::Portal;
use crate::test_rng::XorShift;

/// A 400 × 300 view from `eye` towards the origin.
fn view_from(eye: DVec3) -> View {
    let camera = Camera::look_at(eye, DVec3::ZERO, DVec3::Y, 50.0, 400, 300).unwrap();
    View::new(&camera, 1, None).unwrap()
}

/// The pixel of a world point.
fn pixel(view: &View, p: DVec3) -> (f64, f64) {
    let c = view.clip_of(p);
    (c.x / c.z, c.y / c.z)
}

/// Whether the fixed-point box `b` holds the pixel `(x, y)`.
fn holds(b: &ScreenBox, (x, y): (f64, f64)) -> bool {
    let one = XY_ONE as f64;
    let (x, y) = (x * one, y * one);
    b[0] as f64 <= x && x <= b[2] as f64 && b[1] as f64 <= y && y <= b[3] as f64
}

/// A random unit vector.
fn unit(rng: &mut XorShift) -> DVec3 {
    loop {
        let v = DVec3::new(rng.unit() as f64, rng.unit() as f64, rng.unit() as f64) * 2.0 - 1.0;
        if (0.01..=1.0).contains(&v.length_squared()) {
            return v.normalize();
        }
    }
}

#[test]
fn a_sphere_projects_into_its_box_which_is_tight() {
    let view = view_from(DVec3::new(0.3, 0.2, 5.0));
    let mut rng = XorShift(0x5eed_0001);
    for _ in 0..100 {
        let centre = (unit(&mut rng) * 1.5).as_vec3().as_dvec3();
        let radius = 0.05 + rng.unit() as f64 * 0.5;
        let b = sphere_bounds(&view, centre, radius).unwrap();
        let (mut lo, mut hi) = ((f64::MAX, f64::MAX), (f64::MIN, f64::MIN));
        for _ in 0..4000 {
            let (x, y) = pixel(&view, centre + unit(&mut rng) * radius);
            assert!(b[0] - 1e-9 <= x && x <= b[2] + 1e-9, "{b:?} {x}");
            assert!(b[1] - 1e-9 <= y && y <= b[3] + 1e-9, "{b:?} {y}");
            (lo, hi) = ((lo.0.min(x), lo.1.min(y)), (hi.0.max(x), hi.1.max(y)));
        }
        // Tight: the sampled points reach each side within a pixel.
        assert!(lo.0 - b[0] < 1.0 && lo.1 - b[1] < 1.0, "{b:?} {lo:?}");
        assert!(b[2] - hi.0 < 1.0 && b[3] - hi.1 < 1.0, "{b:?} {hi:?}");
    }
    // Reaching in front of the near plane: no box.
    assert!(sphere_bounds(&view, DVec3::new(0.3, 0.2, 4.5), 0.6).is_none());
}

#[test]
fn a_portal_box_holds_its_sphere_within_its_slab_and_is_thin_edge_on() {
    let view = view_from(DVec3::new(0.0, 0.0, 5.0));
    let mut rng = XorShift(0x5eed_0002);
    for _ in 0..100 {
        let portal = Portal {
            centre: unit(&mut rng),
            radius: 0.1 + rng.unit() as f64 * 0.6,
            normal: unit(&mut rng),
            half_thickness: rng.unit() as f64 * 0.1,
        };
        let b = portal_box(&view, &portal, 0.0).unwrap();
        let mut inside = 0;
        while inside < 2000 {
            let p = unit(&mut rng) * portal.radius * (rng.unit() as f64).cbrt();
            if p.dot(portal.normal).abs() <= portal.half_thickness {
                inside += 1;
                assert!(holds(&b, pixel(&view, portal.centre + p)), "{portal:?}");
            }
        }
    }
    // A thin disc seen edge-on: a box far flatter than its sphere's.
    let disc = Portal {
        centre: DVec3::ZERO,
        radius: 1.0,
        normal: DVec3::Y,
        half_thickness: 0.01,
    };
    let b = portal_box(&view, &disc, 0.0).unwrap();
    let s = sphere_bounds(&view, disc.centre, disc.radius).unwrap();
    assert!(((b[3] - b[1]) as f64 / XY_ONE as f64) < 0.1 * (s[3] - s[1]));
    // Its sphere and cylinder both crossing the near plane: none.
    let near = Portal {
        centre: DVec3::new(0.0, 0.0, 4.5),
        ..disc
    };
    assert!(portal_box(&view, &near, 0.0).is_none());
}

/// A flat 9 × 9-node patch at level 0 under an affine map (`W = 1`) to
/// pixels `(30 + 6i - j, 20 + i + 7j)`, its nodes projected into `xy`.
fn flat_piece(xy: &mut NodeXY) -> (crate::prepare::mip::MipLevel, Vec<crate::fixed::Node>) {
    let frame = Frame::new(Vec3::ZERO, Vec3::X, Vec3::Y, Vec3::Z).unwrap();
    let patch = Patch::new(frame, GridSize::new(9, 9).unwrap(), vec![0; 81], None).unwrap();
    let level = crate::prepare::mip::build_mip_pyramid(&patch).swap_remove(0);
    let p = Projector {
        map: Mat3::from_cols(
            Vec3::new(6.0, 1.0, 0.0),
            Vec3::new(-1.0, 7.0, 0.0),
            Vec3::new(0.0, 0.0, 1.0),
        ),
        t0: Vec3::new(30.0, 20.0, 1.0),
        z_scale: 0.1,
        z_offset: 0.0,
    };
    let mut nodes = Vec::new();
    project_nodes_exact(&level, NodeRange::whole(&level), &p, &mut nodes, xy);
    (level, nodes)
}

/// Pixels to a fixed-point box.
fn fixed_box(b: [f32; 4]) -> ScreenBox {
    b.map(|v| (v * XY_ONE) as i32)
}

#[test]
fn a_patch_behind_a_portal_keeps_exactly_the_cells_in_its_region() {
    let mut xy = NodeXY::default();
    let (level, nodes) = flat_piece(&mut xy);
    let range = NodeRange::whole(&level);
    let measure = |xy: &mut NodeXY, sign: i64, keep: &[ScreenBox]| {
        let mut flags = Vec::new();
        let m = measure_cells(&level, range, xy, (sign, keep), &mut flags, &mut Vec::new());
        (m, flags)
    };
    // The sign under which every cell faces away, and the other.
    let away = [1, -1]
        .into_iter()
        .find(|&s| measure(&mut xy, s, &[]).0.backfacing_cells == 64)
        .unwrap();
    // Two regions: cells touching either are kept, the others dropped.
    let regions = [
        fixed_box([45.0, 50.0, 60.0, 70.0]),
        fixed_box([20.0, 75.0, 24.0, 90.0]),
    ];
    let (m, flags) = measure(&mut xy, away, &regions);
    let mut want = 0;
    for (k, &f) in flags.iter().enumerate() {
        let (ci, cj) = (k % 8, k / 8);
        let corners =
            [(0, 0), (1, 0), (0, 1), (1, 1)].map(|(di, dj)| nodes[(cj + dj) * 9 + ci + di]);
        let (x, y) = (corners.map(|n| n[0]), corners.map(|n| n[1]));
        let cell = [
            *x.iter().min().unwrap(),
            *y.iter().min().unwrap(),
            *x.iter().max().unwrap(),
            *y.iter().max().unwrap(),
        ];
        let kept = regions.iter().any(|r| boxes_touch(r, &cell));
        assert_eq!(f & CELL_DRAW != 0, kept, "cell {ci}, {cj}");
        want += kept as u64;
    }
    assert!(want > 4 && want < 40, "{want}");
    assert_eq!(
        (m.drawable_cells, m.kept_cells, m.backfacing_cells),
        (want, want, 64 - want)
    );
    // No region, or one the piece does not touch: nothing kept; a region
    // holding the piece: no test at all.
    assert_eq!(measure(&mut xy, away, &[]).0.drawable_cells, 0);
    let aside = fixed_box([200.0, 0.0, 300.0, 300.0]);
    assert_eq!(measure(&mut xy, away, &[aside]).0.drawable_cells, 0);
    let all = [i32::MIN, i32::MIN, i32::MAX, i32::MAX];
    let (m, _) = measure(&mut xy, away, &[all]);
    assert_eq!(
        (m.drawable_cells, m.backfacing_cells, m.kept_cells),
        (64, 0, 0)
    );
    // Cells facing the eye: drawn, whatever the regions.
    let (m, _) = measure(&mut xy, -away, &regions);
    assert_eq!((m.drawable_cells, m.kept_cells), (64, 0));
}

#[test]
fn a_patch_box_touches_a_region_only_where_it_lies_on_screen() {
    let view = view_from(DVec3::new(0.0, 0.0, 5.0));
    // The patch box (0..8, 0..8, 0..0) under the map of `flat_piece`: on
    // screen x in 22..78, y in 20..84.
    let map = Mat3::from_cols(
        Vec3::new(6.0, 1.0, 0.0),
        Vec3::new(-1.0, 7.0, 0.0),
        Vec3::new(0.0, 0.0, 1.0),
    );
    let t0 = Vec3::new(30.0, 20.0, 1.0);
    let b = (Vec3::ZERO, Vec3::new(8.0, 8.0, 0.0));
    let touches = |t0: Vec3, r: [f32; 4]| local_box_touches(&view, (&map, t0), b, &[fixed_box(r)]);
    assert!(touches(t0, [70.0, 80.0, 90.0, 90.0]));
    assert!(!touches(t0, [90.0, 0.0, 120.0, 90.0]));
    assert!(!touches(t0, [0.0, 0.0, 20.0, 18.0]));
    // A corner behind the near plane: anywhere.
    assert!(touches(
        Vec3::new(30.0, 20.0, -1.0),
        [300.0, 0.0, 320.0, 10.0]
    ));
}
