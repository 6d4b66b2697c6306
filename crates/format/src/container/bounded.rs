//! Allocation bounded by the bytes a file really has.
//!
//! A reader never sizes a buffer from a count in the file alone: the count is
//! first checked against the bytes that must hold it, so a corrupt or hostile
//! count cannot make the reader allocate more than a small multiple of the
//! file's size.

use crate::FormatError;

/// An empty vector with room for `count` items, each needing at least
/// `min_bytes_per_item` of the `available` bytes. Refuses the count (without
/// allocating) when the bytes cannot hold it.
pub(crate) fn vec_for_count<T>(
    count: usize,
    min_bytes_per_item: usize,
    available: usize,
    what: &str,
) -> Result<Vec<T>, FormatError> {
    let needed = count.saturating_mul(min_bytes_per_item);
    if needed > available {
        return Err(FormatError::Truncated {
            what: format!("{count} {what}"),
            offset: 0,
            needed,
            available,
        });
    }
    #[allow(clippy::disallowed_methods)] // the one checked place
    Ok(Vec::with_capacity(count))
}
