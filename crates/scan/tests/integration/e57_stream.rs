//! `stream_e57` hands out, chunk by chunk, exactly what `read_e57` reads whole: the same
//! scans, poses, positions and colours (or intensity as grey), in order.

use spatch_scan::{read_e57, stream_e57, E57Chunk, ScanError};

use crate::writers::{test_points, write_e57, E57Scan};

#[test]
fn streamed_e57_chunks_equal_the_whole_read() {
    let dir = tempfile::tempdir().unwrap();
    let a = test_points(500, [1000.0, 2000.0, 5.0]);
    let b = test_points(301, [0.0; 3]);
    let h = std::f64::consts::FRAC_1_SQRT_2;
    let path = dir.path().join("two.e57");
    let scan = |points, rotation, translation, colour| E57Scan {
        points,
        rotation,
        translation,
        colour,
    };
    write_e57(
        &path,
        &[
            scan(&a, [1.0, 0.0, 0.0, 0.0], [0.0; 3], true),
            scan(&b, [h, 0.0, 0.0, h], [10.0, 0.0, 1.0], false),
        ],
    );
    let (whole, warnings) = read_e57(&path).unwrap();
    for chunk_points in [7, 300, 1 << 16] {
        let mut scans: Vec<(usize, spatch_scan::Pose, Vec<_>, Vec<_>)> = Vec::new();
        let mut largest = 0;
        let streamed = stream_e57(&path, chunk_points, &mut |c: &E57Chunk<'_>| {
            assert!(!c.positions.is_empty());
            largest = largest.max(c.positions.len());
            if scans.last().is_none_or(|s| s.0 != c.scan) {
                scans.push((c.scan, *c.pose, Vec::new(), Vec::new()));
            }
            let last = scans.last_mut().unwrap();
            assert_eq!(last.1, *c.pose);
            last.2.extend_from_slice(c.positions);
            last.3.extend_from_slice(c.colours.unwrap());
            Ok::<(), ScanError>(())
        })
        .unwrap();
        assert!(largest <= chunk_points);
        assert_eq!(streamed.points, 801);
        assert_eq!(streamed.dropped_non_finite, 0);
        assert_eq!(streamed.warnings, warnings);
        assert_eq!(scans.len(), whole.len());
        for (s, w) in scans.iter().zip(&whole) {
            assert_eq!((s.0, s.1), (w.index, w.pose));
            assert_eq!(s.2, w.positions, "positions bit for bit");
            assert_eq!(Some(&s.3), w.colours.as_ref());
        }
    }
}

#[test]
fn a_refusal_of_the_visitor_stops_the_stream() {
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("one.e57");
    let points = test_points(100, [0.0; 3]);
    write_e57(
        &path,
        &[E57Scan {
            points: &points,
            rotation: [1.0, 0.0, 0.0, 0.0],
            translation: [0.0; 3],
            colour: true,
        }],
    );
    let mut calls = 0;
    let result = stream_e57(&path, 10, &mut |_: &E57Chunk<'_>| {
        calls += 1;
        Err(ScanError::NoInputs)
    });
    assert!(matches!(result, Err(ScanError::NoInputs)));
    assert_eq!(calls, 1);
}
