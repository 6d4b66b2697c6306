//! Degenerate and non-manifold meshes convert; what preparation drops is counted; the error
//! stays bounded.

use spatch_fixtures::shapes;

use super::{convert_report, error, write_obj};
use crate::test_command::TestCommand;

/// Node spacing for the small hand-made meshes below: 1/50 of their unit size, so a cell's
/// reach is small against the shapes.
const SPACING: &str = "0.02";

/// Asserts the surface error is within `cells` node spacings (a cell with an empty corner is
/// not drawn, so along a border or a narrowing tip up to about one cell stays uncovered),
/// and that every node lies on the source or, past a mesh boundary, within half a cell of it
/// (the fitter's boundary reach; up to f32 rounding and half a step).
fn assert_within_cells(report: &serde_json::Value, cells: f64) {
    let spacing: f64 = SPACING.parse().unwrap();
    let max = error(report, "surface_to_patch", "max");
    assert!(
        max <= cells * spacing,
        "surface_to_patch max {max}: {report}"
    );
    assert!(
        error(report, "node_to_surface", "max") <= 0.55 * spacing,
        "{report}"
    );
}

fn f64s(shape: &shapes::Shape) -> Vec<[f64; 3]> {
    shape.positions.iter().map(|p| p.map(f64::from)).collect()
}

/// The unit square cut into 400 slivers fanned from one corner (angles of 0.225° at the
/// corner, aspect ratios up to 500), plus five zero-area triangles (three collinear points):
/// the slivers are kept and the square fully covered (error within a cell of its border),
/// the zero-area triangles dropped and counted.
#[test]
fn sliver_and_zero_area_triangles() {
    let t = TestCommand::new();
    let mut positions = vec![[0.0, 0.0, 0.0]];
    for k in 0..=200 {
        positions.push([1.0, f64::from(k) / 200.0, 0.0]);
    }
    for k in (0..200).rev() {
        positions.push([f64::from(k) / 200.0, 1.0, 0.0]);
    }
    let mut triangles: Vec<[u32; 3]> = (1..401).map(|k| [0, k, k + 1]).collect();
    let base = positions.len() as u32;
    positions.extend([[0.0, 0.0, 0.0], [0.5, 0.5, 0.0], [1.0, 1.0, 0.0]]);
    for _ in 0..5 {
        triangles.push([base, base + 1, base + 2]);
    }
    let obj = write_obj(&t, "slivers.obj", &positions, &triangles);
    let report = convert_report(&t, &obj, &["--spacing", SPACING]);
    assert_eq!(
        report["details"]["prepare"]["dropped_zero_area"], 5,
        "{report}"
    );
    assert_eq!(report["details"]["triangles"], 400, "{report}");
    assert_within_cells(&report, 1.5);
}

/// Two faces whose normals differ by 0.001° are one smooth surface: no crease, one patch,
/// no error beyond quantization.
#[test]
fn nearly_parallel_normals_across_an_edge() {
    let t = TestCommand::new();
    let lift = (0.001f64).to_radians().sin();
    let positions = [
        [0.0, 0.0, 0.0],
        [1.0, 0.0, 0.0],
        [0.0, 1.0, 0.0],
        [1.0, 1.0, lift],
    ];
    let obj = write_obj(&t, "flat.obj", &positions, &[[0, 1, 2], [2, 1, 3]]);
    let report = convert_report(&t, &obj, &[]);
    assert_eq!(report["details"]["edges"]["creases"], 0, "{report}");
    assert_eq!(report["counts"]["patches"], 1, "{report}");
    assert!(
        error(&report, "surface_to_patch", "max_rel") < 1e-4,
        "{report}"
    );
}

/// Two faces folded flat onto each other across an edge (normals exactly opposite): a knife
/// edge, counted, given no edge patch (no direction sees both faces), and both faces still
/// converted and covered.
#[test]
fn exactly_opposite_normals_across_an_edge() {
    let t = TestCommand::new();
    // Both apexes on the same side of the shared edge (0,0,0)-(1,0,0), wound so that each
    // walks the edge the other way: the second face is the first folded back by 180°.
    let positions = [
        [0.0, 0.0, 0.0],
        [1.0, 0.0, 0.0],
        [0.3, 1.0, 0.0],
        [0.7, 1.0, 0.0],
    ];
    let obj = write_obj(&t, "folded.obj", &positions, &[[0, 1, 2], [1, 0, 3]]);
    let report = convert_report(&t, &obj, &["--all-creases", "--spacing", SPACING]);
    let edges = &report["details"]["edges"];
    assert_eq!(edges["knife_edges"], 1, "{report}");
    assert_eq!(edges["edge_patches"], 0, "{report}");
    assert_within_cells(&report, 3.0);
}

/// A cube whose triangles each carry their own three vertices converts exactly like the
/// shared-vertex cube: the duplicates are welded (and counted).
#[test]
fn duplicate_vertices() {
    let t = TestCommand::new();
    let cube = shapes::cube(2.0);
    let shared = write_obj(&t, "shared.obj", &f64s(&cube), &cube.triangles);
    let mut positions = Vec::new();
    let mut triangles = Vec::new();
    for tri in &cube.triangles {
        let k = positions.len() as u32;
        positions.extend(tri.map(|v| cube.positions[v as usize].map(f64::from)));
        triangles.push([k, k + 1, k + 2]);
    }
    let split = write_obj(&t, "split.obj", &positions, &triangles);
    let a = convert_report(&t, &shared, &[]);
    let b = convert_report(&t, &split, &[]);
    assert_eq!(b["details"]["prepare"]["welded_vertices"], 36 - 8, "{b}");
    assert_eq!(a["counts"], b["counts"], "{a}\n{b}");
    assert_eq!(
        error(&a, "surface_to_patch", "max"),
        error(&b, "surface_to_patch", "max")
    );
}

/// Four faces on one edge (a book's pages) and two triangles touching at a single vertex (a
/// bow tie) convert; the non-manifold edge is counted and left out of crease detection;
/// every face is covered (within a few cells at the pages' and bow tie's narrow tips).
#[test]
fn non_manifold_edges_and_bow_tie_vertices() {
    let t = TestCommand::new();
    let book = shapes::non_manifold_fan(4);
    let mut positions = f64s(&book);
    let mut triangles = book.triangles.clone();
    let k = positions.len() as u32;
    // The bow tie, away from the book: two triangles sharing only vertex k.
    positions.extend([
        [3.0, 0.0, 0.0],
        [4.0, 0.5, 0.0],
        [4.0, -0.5, 0.0],
        [2.0, 0.5, 0.0],
        [2.0, -0.5, 0.0],
    ]);
    triangles.push([k, k + 1, k + 2]);
    triangles.push([k, k + 3, k + 4]);
    let obj = write_obj(&t, "tangled.obj", &positions, &triangles);
    let report = convert_report(&t, &obj, &["--spacing", SPACING]);
    assert_eq!(report["details"]["triangles"], 6, "{report}");
    assert_eq!(
        report["details"]["edges"]["non_manifold_edges"], 1,
        "{report}"
    );
    assert_within_cells(&report, 3.0);
}

/// The smallest mesh: one triangle, one patch (a 129-node grid spans it), its nodes on the
/// triangle, its surface within a few cells of the triangle's corners.
#[test]
fn a_single_triangle() {
    let t = TestCommand::new();
    let tri = shapes::single_triangle();
    let obj = write_obj(&t, "one.obj", &f64s(&tri), &tri.triangles);
    let report = convert_report(&t, &obj, &["--spacing", SPACING, "--grid", "129"]);
    assert_eq!(report["counts"]["patches"], 1, "{report}");
    assert_within_cells(&report, 3.0);
}
