//! Typed indices: points of the cloud and views of the sphere of directions.

use std::fmt;

/// Index of a point in the (finite) input cloud.
#[derive(Clone, Copy, PartialEq, Eq, PartialOrd, Ord, Hash, Default)]
pub struct PointId(pub u32);

impl PointId {
    /// A sentinel that names no point.
    pub const INVALID: PointId = PointId(u32::MAX);

    /// The index as `usize`, for slicing.
    pub fn index(self) -> usize {
        self.0 as usize
    }
}

impl fmt::Debug for PointId {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(f, "p#{}", self.0)
    }
}

/// Index of a view direction (see [`view_directions`](crate::view_directions)).
#[derive(Clone, Copy, PartialEq, Eq, PartialOrd, Ord, Hash, Default)]
pub struct ViewId(pub u32);

impl ViewId {
    /// A sentinel that names no view.
    pub const INVALID: ViewId = ViewId(u32::MAX);

    /// The index as `usize`, for slicing.
    pub fn index(self) -> usize {
        self.0 as usize
    }
}

impl fmt::Debug for ViewId {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(f, "v#{}", self.0)
    }
}
