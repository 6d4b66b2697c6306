//! `load_point_cloud` gives exactly what the general PLY reader (`load::ply::load_ply_points`)
//! gives, on files its direct binary path takes and on files it hands over.

use std::path::PathBuf;

use spatch_mesh::load::ply::load_ply_points;
use spatch_mesh::{load_point_cloud, SplitMix64};

/// A temporary file path unique to this test run and `name`.
fn temp_path(name: &str) -> PathBuf {
    std::env::temp_dir().join(format!("spatch-mesh-ply-{}-{name}", std::process::id()))
}

/// One property of a generated vertex record.
#[derive(Clone, Copy)]
enum Property {
    Float(&'static str),
    Uchar(&'static str),
    Double(&'static str),
}

/// The header's `property` lines for `properties`.
fn property_lines(properties: &[Property]) -> String {
    properties
        .iter()
        .map(|p| {
            let (kind, name) = match p {
                Property::Float(n) => ("float", n),
                Property::Uchar(n) => ("uchar", n),
                Property::Double(n) => ("double", n),
            };
            format!("property {kind} {name}\n")
        })
        .collect()
}

/// A binary little-endian PLY with `count` vertices of `properties`, values from `value`
/// (vertex, property index); every 97th vertex gets a NaN in its first float property.
fn write_ply(name: &str, properties: &[Property], count: usize, seed: u64) -> PathBuf {
    let mut text = format!(
        "ply\nformat binary_little_endian 1.0\ncomment generated\nelement vertex {count}\n"
    );
    text.push_str(&property_lines(properties));
    text.push_str("end_header\n");
    let mut bytes = text.into_bytes();
    let mut rng = SplitMix64::new(seed);
    for v in 0..count {
        for (k, p) in properties.iter().enumerate() {
            let x = (rng.next_f64() - 0.5) * 2.0e3 + 1.0e5;
            match p {
                Property::Float(_) if k == 0 && v % 97 == 3 => {
                    bytes.extend_from_slice(&f32::NAN.to_le_bytes())
                }
                Property::Float(_) => bytes.extend_from_slice(&(x as f32).to_le_bytes()),
                Property::Uchar(_) => bytes.push((rng.next_f64() * 256.0) as u8),
                Property::Double(_) => bytes.extend_from_slice(&x.to_le_bytes()),
            }
        }
    }
    let path = temp_path(name);
    std::fs::write(&path, bytes).expect("the temporary file is written");
    path
}

fn assert_same_as_general_reader(path: &PathBuf) {
    let fast = load_point_cloud(path).expect("load_point_cloud reads the file");
    let general = load_ply_points(path).expect("the general reader reads the file");
    assert_eq!(fast.cloud, general.cloud, "{}", path.display());
    assert_eq!(fast.dropped_non_finite, general.dropped_non_finite);
    assert_eq!(fast.warnings.len(), general.warnings.len());
    std::fs::remove_file(path).ok();
}

#[test]
fn binary_layouts_load_exactly_as_the_general_reader_loads_them() {
    use Property::{Double, Float, Uchar};
    let xyz = [Float("x"), Float("y"), Float("z")];
    let normals = [Float("nx"), Float("ny"), Float("nz")];
    let rgb = [Uchar("red"), Uchar("green"), Uchar("blue")];
    let layouts: Vec<(&str, Vec<Property>)> = vec![
        ("xyz.ply", xyz.to_vec()),
        ("xyz_n.ply", [xyz, normals].concat()),
        ("xyz_rgb.ply", [&xyz[..], &rgb[..]].concat()),
        (
            "n_xyz_rgba.ply",
            [&normals[..], &xyz[..], &rgb[..], &[Uchar("alpha")]].concat(),
        ),
        // Not the simple layout: handed to the general reader.
        (
            "xyz_double.ply",
            vec![Double("x"), Double("y"), Double("z")],
        ),
        ("xyz_extra.ply", [&xyz[..], &[Float("intensity")]].concat()),
    ];
    for (k, (name, properties)) in layouts.iter().enumerate() {
        let path = write_ply(name, properties, 5_000, 40 + k as u64);
        assert_same_as_general_reader(&path);
    }
}

/// `path`'s file with `header` lines added before `end_header` and `tail` appended.
fn add_elements(path: &PathBuf, header: &str, tail: &[u8]) {
    let bytes = std::fs::read(path).expect("the file was written");
    let at = bytes
        .windows(10)
        .position(|w| w == b"end_header")
        .expect("a header");
    let mut out = [&bytes[..at], header.as_bytes(), &bytes[at..]].concat();
    out.extend_from_slice(tail);
    std::fs::write(path, out).expect("the file is rewritten");
}

#[test]
fn binary_scans_with_a_range_grid_load_exactly_as_the_general_reader_loads_them() {
    use Property::Float;
    let xyz = [Float("x"), Float("y"), Float("z")];
    let grid = "element range_grid 3\nproperty list uchar int vertex_indices\n";
    // A whole grid (one empty entry, two holding a vertex), and one cut short: the general
    // reader stops once it has the vertices, so neither is read.
    let whole = [0u8, 1, 7, 0, 0, 0, 1, 9, 0, 0, 0];
    for (name, tail) in [("grid.ply", &whole[..]), ("grid_cut.ply", &whole[..4])] {
        let path = write_ply(name, &xyz, 5_000, 60);
        add_elements(&path, grid, tail);
        assert_same_as_general_reader(&path);
    }
    // A later element the general reader cannot parse: its error.
    let path = write_ply("grid_bad.ply", &xyz, 50, 61);
    add_elements(
        &path,
        "element range_grid 3\nproperty list uchar blob v\n",
        &whole,
    );
    assert_eq!(
        load_point_cloud(&path).unwrap_err().to_string(),
        load_ply_points(&path).unwrap_err().to_string()
    );
    std::fs::remove_file(&path).ok();
}

#[test]
fn errors_and_other_layouts_come_from_the_general_reader() {
    // No vertices: the general reader's error.
    let path = write_ply("empty.ply", &[Property::Float("x")], 0, 1);
    assert_eq!(
        load_point_cloud(&path).unwrap_err().to_string(),
        load_ply_points(&path).unwrap_err().to_string()
    );
    std::fs::remove_file(&path).ok();
    // A truncated body.
    let path = write_ply(
        "short.ply",
        &[
            Property::Float("x"),
            Property::Float("y"),
            Property::Float("z"),
        ],
        10,
        2,
    );
    let bytes = std::fs::read(&path).unwrap();
    std::fs::write(&path, &bytes[..bytes.len() - 5]).unwrap();
    assert_eq!(
        load_point_cloud(&path).is_err(),
        load_ply_points(&path).is_err()
    );
    std::fs::remove_file(&path).ok();
    // The raw bunny scan (ASCII PLY) when the shared data is there.
    if let Some(scan) = spatch_fixtures::shared_data("bunny/data/bun000.ply") {
        let fast = load_point_cloud(&scan).unwrap();
        let general = load_ply_points(&scan).unwrap();
        assert_eq!(fast.cloud, general.cloud);
    }
}

/// Extra header lines and the body lines that go with them (elements after the vertices).
type Trailer<'a> = Option<(&'a str, &'a str)>;

/// An ASCII PLY with `count` vertices of `properties` (floats printed as Rust writes f32,
/// uchars as integers), then `trailer` (more header elements and their lines) when given.
fn write_ascii_ply(
    name: &str,
    properties: &[Property],
    count: usize,
    trailer: Trailer<'_>,
) -> PathBuf {
    let mut text = format!("ply\nformat ascii 1.0\nobj_info scanner 1\nelement vertex {count}\n");
    text.push_str(&property_lines(properties));
    if let Some((header, _)) = trailer {
        text.push_str(header);
    }
    text.push_str("end_header\n");
    let mut rng = SplitMix64::new(count as u64);
    for _ in 0..count {
        let values: Vec<String> = properties
            .iter()
            .map(|p| match p {
                Property::Uchar(_) => ((rng.next_f64() * 256.0) as u8).to_string(),
                _ => (((rng.next_f64() - 0.5) * 0.3) as f32).to_string(),
            })
            .collect();
        text.push_str(&values.join(" "));
        text.push('\n');
    }
    if let Some((_, body)) = trailer {
        text.push_str(body);
    }
    let path = temp_path(name);
    std::fs::write(&path, text).expect("the temporary file is written");
    path
}

#[test]
fn ascii_layouts_load_exactly_as_the_general_reader_loads_them() {
    use Property::{Double, Float, Uchar};
    let xyz = [Float("x"), Float("y"), Float("z")];
    let normals = [Float("nx"), Float("ny"), Float("nz")];
    let rgb = [Uchar("red"), Uchar("green"), Uchar("blue")];
    let grid = (
        "element range_grid 3\nproperty list uchar int vertex_indices\n",
        "1 0\n0\n1 2\n",
    );
    let cases: Vec<(&str, Vec<Property>, Trailer<'_>)> = vec![
        ("a_xyz.ply", xyz.to_vec(), None),
        ("a_xyz_grid.ply", xyz.to_vec(), Some(grid)),
        ("a_n_xyz.ply", [normals, xyz].concat(), None),
        ("a_xyz_rgb.ply", [&xyz[..], &rgb[..]].concat(), Some(grid)),
        // Not the simple layout: the general reader's.
        (
            "a_double.ply",
            vec![Double("x"), Double("y"), Double("z")],
            None,
        ),
    ];
    for (name, properties, trailer) in cases {
        let path = write_ascii_ply(name, &properties, 3_000, trailer);
        assert_same_as_general_reader(&path);
    }
    // Spellings the general reader refuses are left to it: the same error.
    let path = temp_path("a_nan.ply");
    std::fs::write(
        &path,
        "ply\nformat ascii 1.0\nelement vertex 2\nproperty float x\nproperty float y\n\
         property float z\nend_header\n0 0 0\nnan 1 1\n",
    )
    .unwrap();
    assert_eq!(
        load_point_cloud(&path).unwrap_err().to_string(),
        load_ply_points(&path).unwrap_err().to_string()
    );
    std::fs::remove_file(&path).ok();
    // The shared ASCII scans.
    for scan in ["bunny/data/bun045.ply", "pointcloud/hoppe_distcap.ply"] {
        if let Some(path) = spatch_fixtures::shared_data(scan) {
            let fast = load_point_cloud(&path).unwrap();
            let general = load_ply_points(&path).unwrap();
            assert_eq!(fast.cloud, general.cloud, "{scan}");
            assert_eq!(
                fast.dropped_non_finite, general.dropped_non_finite,
                "{scan}"
            );
        }
    }
}
