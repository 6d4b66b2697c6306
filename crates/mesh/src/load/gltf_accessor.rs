//! Reading a glTF accessor into f64 components, dequantized.
//!
//! Every component type is read: `FLOAT`, and the integer types `BYTE`, `UNSIGNED_BYTE`,
//! `SHORT`, `UNSIGNED_SHORT`, `UNSIGNED_INT`. A `normalized` integer accessor maps to
//! `[0, 1]` (unsigned: `c / (2^n - 1)`) or `[-1, 1]` (signed: `max(c / (2^(n-1) - 1), -1)`),
//! as the glTF specification (section 3.11) and `KHR_mesh_quantization` define; an integer
//! accessor that is not normalized gives its integer values (positions quantized by
//! gltfpack, whose node transform then scales them back).
//!
//! Elements start at `byteOffset + i * stride` of their view's bytes (stride: the view's
//! `byteStride`, or the element size when packed); each element's range is checked against
//! the view before it is read. Sparse accessors substitute their values at their indices. An
//! accessor with no view reads as zeros (plus sparse values).
//!
//! Cost: O(count * components).
//!
//! Based on: the glTF 2.0 specification (2021) sections 3.6.2 (accessors, sparse) and 3.11
//! (normalized integers); the `KHR_mesh_quantization` extension specification.

use std::borrow::Cow;

use gltf::accessor::{DataType, Dimensions};

/// An accessor's values: `count` elements of `components` f64 values each, flat.
pub(crate) struct AccessorValues {
    /// Components per element (1 for SCALAR, 2 for VEC2, ...).
    pub(crate) components: usize,
    /// `count * components` values.
    pub(crate) values: Vec<f64>,
}

impl AccessorValues {
    /// Element `i` as an array of `N` values (`N` must equal `components`).
    pub(crate) fn get<const N: usize>(&self, i: usize) -> [f64; N] {
        std::array::from_fn(|k| self.values[i * self.components + k])
    }

    /// How many elements there are.
    pub(crate) fn len(&self) -> usize {
        self.values.len() / self.components.max(1)
    }
}

/// Components of an element of `dimensions`, for the shapes vertex data uses.
fn component_count(dimensions: Dimensions) -> usize {
    match dimensions {
        Dimensions::Scalar => 1,
        Dimensions::Vec2 => 2,
        Dimensions::Vec3 => 3,
        Dimensions::Vec4 => 4,
        Dimensions::Mat2 => 4,
        Dimensions::Mat3 => 9,
        Dimensions::Mat4 => 16,
    }
}

/// Bytes of one component.
fn component_size(data_type: DataType) -> usize {
    match data_type {
        DataType::I8 | DataType::U8 => 1,
        DataType::I16 | DataType::U16 => 2,
        DataType::U32 | DataType::F32 => 4,
    }
}

/// Decodes one component at the start of `bytes` (which holds at least its size).
fn read_component(bytes: &[u8], data_type: DataType, normalized: bool) -> f64 {
    let v = match data_type {
        DataType::I8 => f64::from(bytes[0] as i8),
        DataType::U8 => f64::from(bytes[0]),
        DataType::I16 => f64::from(i16::from_le_bytes([bytes[0], bytes[1]])),
        DataType::U16 => f64::from(u16::from_le_bytes([bytes[0], bytes[1]])),
        DataType::U32 => f64::from(u32::from_le_bytes([bytes[0], bytes[1], bytes[2], bytes[3]])),
        DataType::F32 => {
            return f64::from(f32::from_le_bytes([bytes[0], bytes[1], bytes[2], bytes[3]]))
        }
    };
    if !normalized {
        return v;
    }
    match data_type {
        DataType::I8 => (v / 127.0).max(-1.0),
        DataType::U8 => v / 255.0,
        DataType::I16 => (v / 32767.0).max(-1.0),
        DataType::U16 => v / 65535.0,
        _ => v / f64::from(u32::MAX),
    }
}

/// Reads `count` elements of `components` components of `data_type` from `bytes` starting at
/// `offset`, `stride` apart; `None` if one would leave `bytes`.
fn read_elements(
    bytes: &[u8],
    offset: usize,
    stride: usize,
    count: usize,
    components: usize,
    data_type: DataType,
    normalized: bool,
) -> Option<Vec<f64>> {
    let size = component_size(data_type);
    let element = components * size;
    if count == 0 {
        return Some(Vec::new());
    }
    let end = (count - 1)
        .checked_mul(stride)?
        .checked_add(offset)?
        .checked_add(element)?;
    if end > bytes.len() {
        return None;
    }
    let mut out = Vec::with_capacity(count * components);
    for i in 0..count {
        let at = offset + i * stride;
        for k in 0..components {
            out.push(read_component(
                &bytes[at + k * size..],
                data_type,
                normalized,
            ));
        }
    }
    Some(out)
}

/// Reads `accessor` over the resolved view bytes; `None` when its range leaves its view, its
/// view has no bytes, its stride is smaller than its element, or a sparse index is past the
/// count.
pub(crate) fn read_accessor(
    accessor: &gltf::Accessor,
    views: &[Option<Cow<'_, [u8]>>],
) -> Option<AccessorValues> {
    let components = component_count(accessor.dimensions());
    let data_type = accessor.data_type();
    let normalized = accessor.normalized();
    let count = accessor.count();
    let element = components * component_size(data_type);
    let mut values = match accessor.view() {
        Some(view) => {
            let bytes = views.get(view.index())?.as_deref()?;
            let stride = view.stride().unwrap_or(element);
            if stride < element {
                return None;
            }
            let offset = accessor.offset();
            read_elements(
                bytes, offset, stride, count, components, data_type, normalized,
            )?
        }
        None => {
            // Zeros: sized by the count, so only when sparse values back the accessor (a
            // bare count would let a tiny file claim any amount of memory).
            accessor.sparse()?;
            let total = count.checked_mul(components)?;
            if total > views.iter().flatten().map(|v| v.len()).sum::<usize>() * 4 + 4096 {
                return None;
            }
            vec![0.0; total]
        }
    };
    if let Some(sparse) = accessor.sparse() {
        apply_sparse(
            &sparse,
            views,
            components,
            data_type,
            normalized,
            &mut values,
        )?;
    }
    Some(AccessorValues { components, values })
}

/// Substitutes a sparse accessor's values at its indices.
fn apply_sparse(
    sparse: &gltf::accessor::sparse::Sparse,
    views: &[Option<Cow<'_, [u8]>>],
    components: usize,
    data_type: DataType,
    normalized: bool,
    values: &mut [f64],
) -> Option<()> {
    let n = sparse.count();
    let indices = sparse.indices();
    let index_type = match indices.index_type() {
        gltf::accessor::sparse::IndexType::U8 => DataType::U8,
        gltf::accessor::sparse::IndexType::U16 => DataType::U16,
        gltf::accessor::sparse::IndexType::U32 => DataType::U32,
    };
    let index_bytes = views.get(indices.view().index())?.as_deref()?;
    let at = read_elements(
        index_bytes,
        indices.offset(),
        component_size(index_type),
        n,
        1,
        index_type,
        false,
    )?;
    let sparse_values = sparse.values();
    let value_bytes = views.get(sparse_values.view().index())?.as_deref()?;
    let element = components * component_size(data_type);
    let new = read_elements(
        value_bytes,
        sparse_values.offset(),
        element,
        n,
        components,
        data_type,
        normalized,
    )?;
    for (k, &i) in at.iter().enumerate() {
        let start = (i as usize).checked_mul(components)?;
        let target = values.get_mut(start..start + components)?;
        target.copy_from_slice(&new[k * components..(k + 1) * components]);
    }
    Some(())
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn normalized_integers_map_to_the_unit_range() {
        assert_eq!(read_component(&[255], DataType::U8, true), 1.0);
        assert_eq!(read_component(&[0x80], DataType::I8, true), -1.0);
        assert_eq!(read_component(&[0x81], DataType::I8, true), -1.0);
        assert_eq!(read_component(&[0x7f], DataType::I8, true), 1.0);
        assert_eq!(
            read_component(&32767i16.to_le_bytes(), DataType::I16, true),
            1.0
        );
        assert_eq!(
            read_component(&65535u16.to_le_bytes(), DataType::U16, true),
            1.0
        );
        assert_eq!(
            read_component(&1000u16.to_le_bytes(), DataType::U16, false),
            1000.0
        );
    }

    #[test]
    fn elements_past_the_bytes_are_refused() {
        let bytes = [0u8; 16];
        assert!(read_elements(&bytes, 0, 8, 2, 3, DataType::U16, false).is_some());
        assert!(read_elements(&bytes, 4, 8, 2, 3, DataType::U16, false).is_none());
        assert!(read_elements(&bytes, 0, usize::MAX, 2, 1, DataType::U8, false).is_none());
    }
}
