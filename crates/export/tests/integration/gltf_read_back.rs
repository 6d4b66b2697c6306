//! `.gltf` and `.glb` exports read back with the `gltf` crate.

use glam::{DVec3, Vec3};
use gltf::mesh::Mode;
use spatch_export::{export_scene, Content, ExportOptions, Format};

use crate::scenes::{coloured, node_positions, sphere};

/// Reads `bytes` with the gltf crate and returns, per mesh, its mode,
/// vertex count, index count and accessor bounds, with the buffers.
fn read(bytes: &[u8]) -> (gltf::Document, Vec<gltf::buffer::Data>) {
    let (document, buffers, images) = gltf::import_slice(bytes).expect("the gltf crate reads it");
    assert!(images.is_empty());
    (document, buffers)
}

#[test]
fn cells_are_one_indexed_mesh_per_patch_in_both_containers() {
    let scene = sphere();
    for format in [Format::Glb, Format::Gltf] {
        let exported = export_scene(&scene, &ExportOptions::new(format, Content::Cells)).unwrap();
        let (document, buffers) = read(&exported.bytes);
        assert_eq!(document.meshes().count(), scene.patches().len());
        assert_eq!(document.nodes().count(), scene.patches().len());
        let mut triangles = 0;
        for (mesh, patch) in document.meshes().zip(scene.patches()) {
            let primitive = mesh.primitives().next().unwrap();
            assert_eq!(primitive.mode(), Mode::Triangles);
            let reader = primitive.reader(|b| Some(&buffers[b.index()]));
            let positions: Vec<[f32; 3]> = reader.read_positions().unwrap().collect();
            let normals: Vec<[f32; 3]> = reader.read_normals().unwrap().collect();
            let indices: Vec<u32> = reader.read_indices().unwrap().into_u32().collect();
            // The sphere's patches are full: every node is a shared vertex.
            assert_eq!(positions.len(), patch.grid().node_count());
            assert_eq!(normals.len(), positions.len());
            let cells =
                (usize::from(patch.grid().cols()) - 1) * (usize::from(patch.grid().rows()) - 1);
            assert_eq!(indices.len(), cells * 6);
            assert!(indices.iter().all(|&i| (i as usize) < positions.len()));
            let bounds = primitive.bounding_box();
            let (lo, hi) = positions
                .iter()
                .fold((Vec3::INFINITY, Vec3::NEG_INFINITY), |(lo, hi), &p| {
                    (lo.min(p.into()), hi.max(p.into()))
                });
            assert_eq!((bounds.min, bounds.max), (lo.to_array(), hi.to_array()));
            for n in normals {
                assert!((Vec3::from(n).length() - 1.0).abs() < 1e-5);
            }
            triangles += indices.len() / 3;
        }
        assert_eq!(triangles, exported.triangles);
    }
}

#[test]
fn placed_vertices_are_the_scene_nodes() {
    let scene = sphere();
    let exported = export_scene(&scene, &ExportOptions::new(Format::Glb, Content::Nodes)).unwrap();
    let (document, buffers) = read(&exported.bytes);
    let mut placed = Vec::new();
    for node in document.nodes() {
        let (t, _, _) = node.transform().decomposed();
        let primitive = node.mesh().unwrap().primitives().next().unwrap();
        let reader = primitive.reader(|b| Some(&buffers[b.index()]));
        placed.extend(
            reader
                .read_positions()
                .unwrap()
                .map(|p| Vec3::from(t).as_dvec3() + Vec3::from(p).as_dvec3()),
        );
    }
    let expected = node_positions(&scene);
    assert_eq!(placed.len(), expected.len());
    for (a, b) in placed.iter().zip(&expected) {
        assert!((*a - *b).length() < 1e-4, "{a} {b}");
    }
}

#[test]
fn points_and_colours_read_back() {
    for alpha in [255, 100] {
        let scene = coloured(DVec3::new(3.0, 2.0, 1.0), alpha);
        let exported =
            export_scene(&scene, &ExportOptions::new(Format::Glb, Content::Nodes)).unwrap();
        let (document, buffers) = read(&exported.bytes);
        let mut count = 0;
        for mesh in document.meshes() {
            let primitive = mesh.primitives().next().unwrap();
            assert_eq!(primitive.mode(), Mode::Points);
            assert!(primitive.indices().is_none());
            let reader = primitive.reader(|b| Some(&buffers[b.index()]));
            let colours: Vec<[f32; 4]> = reader.read_colors(0).unwrap().into_rgba_f32().collect();
            assert_eq!(colours.len(), 11);
            // Node 1 is sRGB (20, 235, 128): linear (0.0070, 0.8308, 0.2159).
            let c = colours[1];
            assert!(
                (c[0] - 0.0070).abs() < 1e-3 && (c[1] - 0.8308).abs() < 1e-3,
                "{c:?}"
            );
            assert!((c[3] - f32::from(alpha) / 255.0).abs() < 1e-6);
            count += colours.len();
        }
        assert_eq!(count, node_positions(&scene).len());
        let material = document.materials().next().unwrap();
        let blend = alpha < 255;
        assert_eq!(
            material.alpha_mode() == gltf::material::AlphaMode::Blend,
            blend
        );
    }
}

#[test]
fn an_empty_scene_is_a_valid_empty_document() {
    let scene =
        spatch_format::Scene::new(DVec3::ZERO, spatch_format::ColourChannel::None, vec![]).unwrap();
    for format in [Format::Glb, Format::Gltf] {
        let exported = export_scene(&scene, &ExportOptions::new(format, Content::Cells)).unwrap();
        let (document, _) = read(&exported.bytes);
        assert_eq!(document.meshes().count(), 0);
        assert_eq!(document.scenes().count(), 0);
    }
}
