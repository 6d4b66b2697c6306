//! A summary of what a scene and its file hold (for `spatch stats`).

use std::collections::BTreeMap;

use glam::DVec3;

use crate::{ContainerInfo, DisplacementWidth, GridSize, Scene};

/// Minimum and maximum of one quantity.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Range {
    /// Smallest value.
    pub min: f64,
    /// Largest value.
    pub max: f64,
}

impl Range {
    fn of(values: impl Iterator<Item = f64>) -> Option<Self> {
        values.fold(None, |acc, v| match acc {
            None => Some(Self { min: v, max: v }),
            Some(r) => Some(Self {
                min: r.min.min(v),
                max: r.max.max(v),
            }),
        })
    }
}

/// Counts, sizes and ranges of a scene as stored in a file.
#[derive(Debug, Clone, PartialEq)]
pub struct SceneSummary {
    /// Number of patches.
    pub patches: usize,
    /// All grid nodes.
    pub nodes: usize,
    /// Non-empty nodes.
    pub filled_nodes: usize,
    /// Drawable cells (all four corners filled).
    pub drawable_cells: usize,
    /// Patch counts per displacement width.
    pub displacement_bits: BTreeMap<u8, usize>,
    /// Patch counts per grid size.
    pub grids: BTreeMap<GridSize, usize>,
    /// Model-space bounds of the filled nodes.
    pub bounds: Option<(DVec3, DVec3)>,
    /// Ranges of `|ax|`, `|ay|`, `|az|` over the patches.
    pub frame_lengths: Option<[Range; 3]>,
    /// Stored DISP bits per node (all nodes).
    pub displacement_bits_per_node: f64,
    /// Stored COLR bits per filled node (0 without per-node colour).
    pub colour_bits_per_node: f64,
}

impl SceneSummary {
    /// Summarizes `scene` as stored in a file described by `info`.
    pub fn new(scene: &Scene, info: &ContainerInfo) -> Self {
        let patches = scene.patches();
        let mut displacement_bits = BTreeMap::new();
        let mut grids = BTreeMap::new();
        let mut drawable_cells = 0;
        for patch in patches {
            let bits = match patch.displacement_width() {
                DisplacementWidth::Bits8 => 8,
                DisplacementWidth::Bits16 => 16,
            };
            *displacement_bits.entry(bits).or_insert(0) += 1;
            *grids.entry(patch.grid()).or_insert(0) += 1;
            let g = patch.grid();
            for j in 0..usize::from(g.rows()) - 1 {
                for i in 0..usize::from(g.cols()) - 1 {
                    drawable_cells += usize::from(patch.cell_is_drawable(i, j));
                }
            }
        }
        let length =
            |k: usize| Range::of(patches.iter().map(|p| f64::from(p.frame().lengths()[k])));
        let frame_lengths = match (length(0), length(1), length(2)) {
            (Some(x), Some(y), Some(z)) => Some([x, y, z]),
            _ => None,
        };
        let stored = |tag: &str| {
            info.sections
                .iter()
                .filter(|s| s.tag == tag)
                .map(|s| s.stored_len)
                .sum::<usize>() as f64
                * 8.0
        };
        let per = |bits: f64, count: usize| if count == 0 { 0.0 } else { bits / count as f64 };
        let (nodes, filled_nodes) = (scene.node_count(), scene.filled_node_count());
        Self {
            patches: patches.len(),
            nodes,
            filled_nodes,
            drawable_cells,
            displacement_bits,
            grids,
            bounds: scene.bounds(),
            frame_lengths,
            displacement_bits_per_node: per(stored("DISP"), nodes),
            colour_bits_per_node: per(stored("COLR"), filled_nodes),
        }
    }
}
