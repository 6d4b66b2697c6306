//! Heights that overflow 8-bit displacements.

use spatch_fixtures::shapes;

use super::{convert_report, error};
use crate::test_command::TestCommand;

/// Regions up to 80° wide and 257 nodes across on a fine sphere: a region's height range
/// then needs more than 255 steps of the error budget (a tenth of the spacing), so those
/// patches take 16-bit codes, and every node stays within that budget of the surface.
#[test]
fn displacements_that_overflow_8_bits() {
    let t = TestCommand::new();
    std::fs::write(
        t.path("ball.obj"),
        shapes::uv_sphere(1.0, 128, 64).to_obj([0.0; 3]),
    )
    .unwrap();
    let wide = convert_report(&t, "ball.obj", &["--cone-angle", "80", "--grid", "257"]);
    assert!(
        wide["details"]["wide_patches"].as_u64().unwrap() > 0,
        "no 16-bit patch: {wide}"
    );
    let spacing = wide["details"]["spacing"].as_f64().unwrap();
    // Half a step (at most a tenth of the spacing) plus the faceting of the source.
    assert!(
        error(&wide, "node_to_surface", "max") <= 0.1 * spacing + 1e-4,
        "{wide}"
    );
    // The defaults (30° regions of 17 × 17) stay 8-bit on the same sphere.
    let narrow = convert_report(&t, "ball.obj", &[]);
    assert_eq!(narrow["details"]["wide_patches"], 0, "{narrow}");
}
