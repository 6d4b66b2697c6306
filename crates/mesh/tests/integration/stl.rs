//! The STL reader on files written by `stl_io` (binary) and by hand (ASCII): the same mesh
//! comes back, and malformed files give one typed error.

use std::path::{Path, PathBuf};

use spatch_fixtures::{shapes, Shape};
use spatch_mesh::{load_mesh, prepare_mesh, LoadWarning, MeshError, PrepareOptions, SyntaxProblem};
use stl_io::{Normal, Triangle, Vertex};

fn write(dir: &Path, name: &str, bytes: &[u8]) -> PathBuf {
    let path = dir.join(name);
    std::fs::write(&path, bytes).unwrap();
    path
}

fn stl_triangles(shape: &Shape) -> Vec<Triangle> {
    shape
        .triangles
        .iter()
        .map(|t| Triangle {
            normal: Normal::new([0.0; 3]),
            vertices: t.map(|i| Vertex::new(shape.positions[i as usize])),
        })
        .collect()
}

fn binary_stl(shape: &Shape) -> Vec<u8> {
    let mut out = Vec::new();
    stl_io::write_stl(&mut out, stl_triangles(shape).iter()).unwrap();
    out
}

fn ascii_stl(shape: &Shape) -> String {
    let mut out = String::from("solid test\n");
    for t in &shape.triangles {
        out.push_str("  facet normal 0 0 0\n    outer loop\n");
        for &i in t {
            let p = shape.positions[i as usize];
            out.push_str(&format!("      vertex {:e} {:e} {:e}\n", p[0], p[1], p[2]));
        }
        out.push_str("    endloop\n  endfacet\n");
    }
    out.push_str("endsolid test\n");
    out
}

/// Loads, welds and checks the result against the shape: same triangle count, same vertex
/// count after welding, and every triangle's corners at the shape's positions in order.
fn assert_same_as_shape(path: &Path, shape: &Shape) {
    let loaded = load_mesh(path).unwrap();
    assert_eq!(loaded.mesh.triangles.len(), shape.triangles.len());
    for (t, expected) in loaded.mesh.triangles.iter().zip(&shape.triangles) {
        for k in 0..3 {
            let got = loaded.mesh.world_position(spatch_mesh::VertexId(t[k]));
            let want = shape.positions[expected[k] as usize];
            for axis in 0..3 {
                assert!(
                    (got[axis] - f64::from(want[axis])).abs() < 1e-6,
                    "{got} vs {want:?}"
                );
            }
        }
    }
    let (welded, _) = prepare_mesh(&loaded.mesh, &PrepareOptions::default());
    assert_eq!(welded.positions.len(), shape.positions.len());
    assert_eq!(welded.triangles.len(), shape.triangles.len());
}

#[test]
fn binary_stl_from_stl_io_loads_and_welds() {
    let dir = tempfile::tempdir().unwrap();
    let shape = shapes::torus(2.0, 0.5, 24, 12);
    let path = write(dir.path(), "torus.stl", &binary_stl(&shape));
    assert_same_as_shape(&path, &shape);
    // stl_io reads back what it wrote: the two readers agree on the triangle count.
    let mut file = std::fs::File::open(&path).unwrap();
    let reference = stl_io::read_stl(&mut file).unwrap();
    assert_eq!(reference.faces.len(), shape.triangles.len());
}

#[test]
fn binary_stl_whose_header_says_solid_is_still_binary() {
    let dir = tempfile::tempdir().unwrap();
    let shape = shapes::cube(1.0);
    let mut bytes = binary_stl(&shape);
    bytes[..12].copy_from_slice(b"solid binary");
    let path = write(dir.path(), "cube.STL", &bytes);
    assert_same_as_shape(&path, &shape);
}

#[test]
fn ascii_stl_loads_and_welds() {
    let dir = tempfile::tempdir().unwrap();
    let shape = shapes::icosphere(1.5, 2);
    let path = write(dir.path(), "ball.stl", ascii_stl(&shape).as_bytes());
    assert_same_as_shape(&path, &shape);
    // Upper-case keywords, CR LF line ends and two solids in one file.
    let text = ascii_stl(&shape).to_uppercase().replace('\n', "\r\n");
    let path = write(dir.path(), "two.stl", format!("{text}{text}").as_bytes());
    let loaded = load_mesh(&path).unwrap();
    assert_eq!(loaded.mesh.triangles.len(), 2 * shape.triangles.len());
}

#[test]
fn ascii_stl_quad_loop_is_fanned_and_counted() {
    let dir = tempfile::tempdir().unwrap();
    let text = "solid q\nfacet normal 0 0 1\nouter loop\nvertex 0 0 0\nvertex 1 0 0\n\
                vertex 1 1 0\nvertex 0 1 0\nendloop\nendfacet\nendsolid q\n";
    let loaded = load_mesh(write(dir.path(), "quad.stl", text.as_bytes())).unwrap();
    assert_eq!(loaded.mesh.triangles, vec![[0, 1, 2], [0, 2, 3]]);
    assert!(matches!(
        loaded.warnings[..],
        [LoadWarning::PolygonsTriangulated { count: 1 }]
    ));
}

#[test]
fn malformed_stl_gives_one_typed_error() {
    let dir = tempfile::tempdir().unwrap();
    let shape = shapes::cube(1.0);
    let bytes = binary_stl(&shape);
    // Truncated binary: the count no longer matches the length.
    let cut = write(dir.path(), "cut.stl", &bytes[..bytes.len() - 7]);
    let err = load_mesh(&cut).unwrap_err();
    assert!(matches!(
        err,
        MeshError::StlLength {
            declared: 12,
            length: 677,
            ..
        }
    ));
    let text = err.to_string();
    assert!(text.starts_with(&cut.display().to_string()) && !text.contains('\n'));
    // A binary count far larger than the file never sizes an allocation.
    let mut huge = bytes.clone();
    huge[80..84].copy_from_slice(&u32::MAX.to_le_bytes());
    let huge = write(dir.path(), "huge.stl", &huge);
    assert!(matches!(load_mesh(&huge), Err(MeshError::StlLength { .. })));
    // NaN in a binary vertex names the vertex.
    let mut nan = bytes.clone();
    nan[84 + 12 + 12 + 4..84 + 12 + 12 + 8].copy_from_slice(&f32::NAN.to_le_bytes());
    let nan = write(dir.path(), "nan.stl", &nan);
    assert!(matches!(
        load_mesh(&nan),
        Err(MeshError::NonFinite {
            element: spatch_mesh::Element::Vertex(1),
            ..
        })
    ));
    let cases: [(&str, &str, usize, SyntaxProblem); 4] = [
        (
            "word.stl",
            "solid a\nfacet normal 0 0 1\nouter loop\nvertex 0 zero 0\n",
            4,
            SyntaxProblem::NotANumber { column: 3 },
        ),
        (
            "open.stl",
            "solid a\nfacet normal 0 0 1\nouter loop\nvertex 0 0 0\nvertex 1 0 0\n",
            5,
            SyntaxProblem::StlUnclosedLoop,
        ),
        (
            "two.stl",
            "solid a\nouter loop\nvertex 0 0 0\nvertex 1 0 0\nendloop\n",
            5,
            SyntaxProblem::FaceTooSmall { len: 2 },
        ),
        (
            "stray.stl",
            "solid a\nvertex 0 0 0\n",
            2,
            SyntaxProblem::StlVertexOutsideLoop,
        ),
    ];
    for (name, text, line, problem) in cases {
        let path = write(dir.path(), name, text.as_bytes());
        match load_mesh(&path) {
            Err(MeshError::Syntax {
                line: l,
                problem: p,
                ..
            }) => assert_eq!((l, p), (line, problem), "{name}"),
            other => panic!("{name}: {other:?}"),
        }
    }
    // ASCII with no facets has no faces.
    let empty = write(dir.path(), "empty.stl", b"solid a\nendsolid a\n");
    assert!(matches!(load_mesh(&empty), Err(MeshError::NoFaces { .. })));
}
