//! PLY `tristrips`: a grid written as strips loads to the same triangles, with the same
//! winding, as the grid written as a face list.

use std::path::{Path, PathBuf};

use spatch_mesh::{load_mesh, MeshError, PlyProblem};

fn write(dir: &Path, name: &str, bytes: &[u8]) -> PathBuf {
    let path = dir.join(name);
    std::fs::write(&path, bytes).unwrap();
    path
}

const COLUMNS: u32 = 5;
const ROWS: u32 = 3;

fn vertex(row: u32, column: u32) -> u32 {
    row * (COLUMNS + 1) + column
}

/// The grid's counter-clockwise triangles (seen from +z), row by row.
fn grid_faces() -> Vec<[u32; 3]> {
    let mut out = Vec::new();
    for r in 0..ROWS {
        for c in 0..COLUMNS {
            let (a, b) = (vertex(r + 1, c), vertex(r, c));
            let (d, e) = (vertex(r + 1, c + 1), vertex(r, c + 1));
            out.push([a, b, d]);
            out.push([d, b, e]);
        }
    }
    out
}

/// One strip per row: top, bottom, top, bottom, ... (so the first triangle is counter-clockwise).
fn grid_strip_rows() -> Vec<Vec<i64>> {
    (0..ROWS)
        .map(|r| {
            (0..=COLUMNS)
                .flat_map(|c| [vertex(r + 1, c), vertex(r, c)])
                .map(i64::from)
                .collect()
        })
        .collect()
}

fn header(faces_line: &str, count: usize) -> String {
    let vertices = (ROWS + 1) * (COLUMNS + 1);
    let mut out = format!(
        "ply\nformat ascii 1.0\nelement vertex {vertices}\nproperty float x\nproperty float y\n\
         property float z\nelement {faces_line} {count}\nproperty list int int vertex_indices\n\
         end_header\n"
    );
    for r in 0..=ROWS {
        for c in 0..=COLUMNS {
            out.push_str(&format!("{c} {r} 0\n"));
        }
    }
    out
}

fn list_line(list: &[i64]) -> String {
    let items: Vec<String> = list.iter().map(i64::to_string).collect();
    format!("{} {}\n", list.len(), items.join(" "))
}

/// Triangles as sets of rotations, so `[a, b, c]` equals `[b, c, a]` but not `[a, c, b]`.
fn canonical(t: [u32; 3]) -> [u32; 3] {
    let k = (0..3).min_by_key(|&k| t[k]).unwrap();
    [t[k], t[(k + 1) % 3], t[(k + 2) % 3]]
}

fn sorted(triangles: &[[u32; 3]]) -> Vec<[u32; 3]> {
    let mut out: Vec<[u32; 3]> = triangles.iter().copied().map(canonical).collect();
    out.sort_unstable();
    out
}

#[test]
fn strips_match_the_face_list_in_count_and_winding() {
    let dir = tempfile::tempdir().unwrap();
    let faces = grid_faces();
    let mut face_text = header("face", faces.len());
    for f in &faces {
        face_text.push_str(&list_line(&f.map(i64::from)));
    }
    let from_faces = load_mesh(write(dir.path(), "faces.ply", face_text.as_bytes())).unwrap();

    // One list per row, as some scanners write it...
    let rows = grid_strip_rows();
    let mut rows_text = header("tristrips", rows.len());
    for row in &rows {
        rows_text.push_str(&list_line(row));
    }
    let from_rows = load_mesh(write(dir.path(), "rows.ply", rows_text.as_bytes())).unwrap();

    // ... and one list with -1 restarts, as the Stanford repository's files do.
    let joined: Vec<i64> = rows.join(&-1);
    let one_text = header("tristrips", 1) + &list_line(&joined);
    let from_one = load_mesh(write(dir.path(), "one.ply", one_text.as_bytes())).unwrap();

    let expected = sorted(&from_faces.mesh.triangles);
    assert_eq!(expected.len(), (2 * ROWS * COLUMNS) as usize);
    assert_eq!(sorted(&from_rows.mesh.triangles), expected);
    assert_eq!(sorted(&from_one.mesh.triangles), expected);
    // Every triangle faces +z, as the face list's do.
    for t in &from_one.mesh.triangles {
        let n = from_one.mesh.face_normal(spatch_mesh::FaceId(
            from_one.mesh.triangles.iter().position(|x| x == t).unwrap() as u32,
        ));
        assert!(n.z > 0.99, "{t:?} faces {n}");
    }
}

#[test]
fn strip_index_out_of_range_is_refused() {
    let dir = tempfile::tempdir().unwrap();
    let text = header("tristrips", 2) + &list_line(&[0, 1, 7]) + &list_line(&[0, 1, 99]);
    let path = write(dir.path(), "bad.ply", text.as_bytes());
    match load_mesh(&path) {
        Err(MeshError::PlyStructure {
            problem:
                PlyProblem::StripIndexOutOfRange {
                    strip: 1,
                    index: 99,
                    vertex_count: 24,
                },
            ..
        }) => {}
        other => panic!("{other:?}"),
    }
}
