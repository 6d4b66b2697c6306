//! Pass 3 of the range image: pixels that see a farther surface through a sampling hole of
//! the front one are emptied (gap filling then closes them from the front surface).

use super::{RangeImage, EMPTY_DEPTH, SEE_THROUGH_NEIGHBOURS};

/// Empties pixels that see a farther surface through a hole of the front one (pass 3).
pub(super) fn remove_see_through(image: &mut RangeImage, jump: f32) {
    let (w, h) = (image.geometry.width, image.geometry.height);
    let depth = &image.depth;
    let mut cleared = Vec::new();
    for j in 1..h.saturating_sub(1) {
        for i in 1..w - 1 {
            let d = depth[j * w + i];
            if !d.is_finite() {
                continue;
            }
            let mut nearer = 0;
            for (di, dj) in NEIGHBOURS_8 {
                let n = depth[(j as isize + dj) as usize * w + (i as isize + di) as usize];
                if n > d + jump {
                    nearer += 1;
                }
            }
            if nearer >= SEE_THROUGH_NEIGHBOURS {
                cleared.push(j * w + i);
            }
        }
    }
    for k in cleared {
        image.depth[k] = EMPTY_DEPTH;
        if let Some(c) = image.colour.as_mut() {
            c[k] = [0; 4];
        }
    }
}

/// Offsets of the 8 neighbours of a pixel.
const NEIGHBOURS_8: [(isize, isize); 8] = [
    (-1, -1),
    (0, -1),
    (1, -1),
    (-1, 0),
    (1, 0),
    (-1, 1),
    (0, 1),
    (1, 1),
];
