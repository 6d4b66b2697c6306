//! Typed indices: a face, a vertex or a material of a [`TriangleMesh`](crate::TriangleMesh).
//!
//! Each wraps a `u32`, has an `INVALID` sentinel (`u32::MAX`) and prints shortly in `Debug`
//! (`f#12`, `v#7`, `m#0`), so logs of large index lists stay readable.

use std::fmt;

macro_rules! typed_id {
    ($(#[$doc:meta])* $name:ident, $prefix:literal) => {
        $(#[$doc])*
        #[derive(Clone, Copy, PartialEq, Eq, Hash, PartialOrd, Ord)]
        pub struct $name(pub u32);

        impl $name {
            /// The sentinel for "no such item" (`u32::MAX`).
            pub const INVALID: Self = Self(u32::MAX);

            /// The id as a `usize`, for indexing slices.
            #[inline]
            pub const fn index(self) -> usize {
                self.0 as usize
            }

            /// The id of slice position `index`, or `None` when it does not fit in a `u32`
            /// (or would equal the `INVALID` sentinel).
            #[inline]
            pub fn from_index(index: usize) -> Option<Self> {
                u32::try_from(index).ok().filter(|&i| i != u32::MAX).map(Self)
            }

            /// Whether this is not the `INVALID` sentinel.
            #[inline]
            pub const fn is_valid(self) -> bool {
                self.0 != u32::MAX
            }
        }

        impl fmt::Debug for $name {
            fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
                if self.is_valid() {
                    write!(f, concat!($prefix, "#{}"), self.0)
                } else {
                    f.write_str(concat!($prefix, "#INVALID"))
                }
            }
        }

        impl fmt::Display for $name {
            fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
                fmt::Debug::fmt(self, f)
            }
        }
    };
}

typed_id!(
    /// Index of a triangle in [`TriangleMesh::triangles`](crate::TriangleMesh::triangles).
    FaceId,
    "f"
);
typed_id!(
    /// Index of a vertex in [`TriangleMesh::positions`](crate::TriangleMesh::positions).
    VertexId,
    "v"
);
typed_id!(
    /// Index of an edge in a [`FaceAdjacency`](crate::FaceAdjacency).
    EdgeId,
    "e"
);
typed_id!(
    /// Index of a material in [`TriangleMesh::materials`](crate::TriangleMesh::materials).
    MaterialId,
    "m"
);

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn debug_is_short() {
        assert_eq!(format!("{:?}", FaceId(12)), "f#12");
        assert_eq!(format!("{:?}", VertexId(3)), "v#3");
        assert_eq!(format!("{:?}", MaterialId::INVALID), "m#INVALID");
        assert_eq!(format!("{:?}", [FaceId(1), FaceId(2)]), "[f#1, f#2]");
    }

    #[test]
    fn from_index_rejects_what_does_not_fit() {
        assert_eq!(FaceId::from_index(5), Some(FaceId(5)));
        assert_eq!(FaceId::from_index(u32::MAX as usize), None);
        assert!(!FaceId::INVALID.is_valid());
    }
}
