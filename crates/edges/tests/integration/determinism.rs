//! Same input and options, same patches, whatever the thread count.

use spatch_edges::{generate_edge_patches, EdgeOptions};
use spatch_fixtures::shapes;
use spatch_mesh::build_face_adjacency;

use crate::surface::{frustum, mesh_of};

#[test]
fn patches_do_not_depend_on_threads() {
    for mesh in [mesh_of(&shapes::cube(2.0)), frustum(60.0, 64)] {
        let adjacency = build_face_adjacency(&mesh);
        let run = |threads: usize| {
            rayon::ThreadPoolBuilder::new()
                .num_threads(threads)
                .build()
                .unwrap()
                .install(|| {
                    generate_edge_patches(&mesh, &adjacency, &[], 0.05, &EdgeOptions::default())
                        .unwrap()
                })
        };
        let (one, stats_one) = run(1);
        let (two, stats_two) = run(2);
        assert_eq!(one, two);
        assert_eq!(stats_one, stats_two);
        assert_eq!(run(1).0, one);
    }
}
