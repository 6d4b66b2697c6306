//! The scalar types a PLY header may name for a property, their sizes and how their bytes
//! read.

/// A PLY property's scalar type (both spellings: `uchar` and `uint8`, `float` and
/// `float32`, ...).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum PlyScalar {
    /// `char` / `int8`.
    I8,
    /// `uchar` / `uint8`.
    U8,
    /// `short` / `int16`.
    I16,
    /// `ushort` / `uint16`.
    U16,
    /// `int` / `int32`.
    I32,
    /// `uint` / `uint32`.
    U32,
    /// `float` / `float32`.
    F32,
    /// `double` / `float64`.
    F64,
}

impl PlyScalar {
    /// The type a header names, `None` for a word that names none.
    pub fn parse(name: &str) -> Option<PlyScalar> {
        Some(match name {
            "char" | "int8" => PlyScalar::I8,
            "uchar" | "uint8" => PlyScalar::U8,
            "short" | "int16" => PlyScalar::I16,
            "ushort" | "uint16" => PlyScalar::U16,
            "int" | "int32" => PlyScalar::I32,
            "uint" | "uint32" => PlyScalar::U32,
            "float" | "float32" => PlyScalar::F32,
            "double" | "float64" => PlyScalar::F64,
            _ => return None,
        })
    }

    /// Bytes of one value in a binary body.
    pub fn size(self) -> usize {
        match self {
            PlyScalar::I8 | PlyScalar::U8 => 1,
            PlyScalar::I16 | PlyScalar::U16 => 2,
            PlyScalar::I32 | PlyScalar::U32 | PlyScalar::F32 => 4,
            PlyScalar::F64 => 8,
        }
    }

    /// The value at the start of `b` (at least [`PlyScalar::size`] bytes), big-endian when
    /// `big`.
    pub fn read(self, b: &[u8], big: bool) -> f64 {
        macro_rules! num {
            ($t:ty, $n:expr) => {{
                let mut a = [0u8; $n];
                a.copy_from_slice(&b[..$n]);
                f64::from(if big {
                    <$t>::from_be_bytes(a)
                } else {
                    <$t>::from_le_bytes(a)
                })
            }};
        }
        match self {
            PlyScalar::I8 => f64::from(b[0] as i8),
            PlyScalar::U8 => f64::from(b[0]),
            PlyScalar::I16 => num!(i16, 2),
            PlyScalar::U16 => num!(u16, 2),
            PlyScalar::I32 => num!(i32, 4),
            PlyScalar::U32 => num!(u32, 4),
            PlyScalar::F32 => num!(f32, 4),
            PlyScalar::F64 => num!(f64, 8),
        }
    }
}
