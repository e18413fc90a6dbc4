//! What flattening a mask's cell hierarchy keeps, counted over the cell graph before any of it
//! is made. A file of a few kilobytes whose cells nest arrays expands to billions of polygons:
//! counting while expanding would first hold gigabytes of placements waiting on the stack.

/// One cell as the count sees it.
pub(super) struct CellSize {
    /// Bytes its own polygons and notes take once flattened ([`polygon_bytes`], [`text_bytes`]).
    pub own_bytes: usize,
    /// Each placement: the placed cell's index and how many instances it places.
    pub children: Vec<(usize, usize)>,
}

/// Bytes a flattened polygon of `points` vertices takes (its `Vec` and its `[f64; 2]` points).
pub(super) fn polygon_bytes(points: usize) -> usize {
    24usize.saturating_add(points.saturating_mul(16))
}

/// Bytes a flattened note of `len` bytes takes.
pub(super) fn text_bytes(len: usize) -> usize {
    24usize.saturating_add(len)
}

/// Bytes one placed instance takes while the expansion holds it (cell, transform, depth).
const INSTANCE_BYTES: usize = 64;

/// Most bytes an import's expansion may keep: a whole display's mask of a million pixels with
/// a few polygons each is about 100 MiB.
pub(super) const MAX_FLAT_BYTES: usize = 512 << 20;

/// Deepest placement nesting; a cycle in the cell graph ends here.
pub(super) const MAX_DEPTH: usize = 32;

/// Why a hierarchy cannot be expanded.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(super) enum FlatSizeError {
    /// Placements nest deeper than [`MAX_DEPTH`] levels (a crafted or cyclic file).
    TooDeep,
    /// The expansion would keep more than [`MAX_FLAT_BYTES`].
    TooLarge,
}

/// The bytes the expansion of `top` keeps, each cell counted once however often it is placed.
///
/// # Errors
/// [`FlatSizeError::TooDeep`] past [`MAX_DEPTH`] levels, [`FlatSizeError::TooLarge`] past
/// [`MAX_FLAT_BYTES`] (sums saturate, so a count near `usize::MAX` is too large, not wrapped).
pub(super) fn flattened_bytes(cells: &[CellSize], top: usize) -> Result<usize, FlatSizeError> {
    fn walk(
        cells: &[CellSize],
        at: usize,
        depth: usize,
        memo: &mut [Option<usize>],
    ) -> Result<usize, FlatSizeError> {
        if depth > MAX_DEPTH {
            return Err(FlatSizeError::TooDeep);
        }
        if let Some(bytes) = memo[at] {
            return Ok(bytes);
        }
        let mut bytes = cells[at].own_bytes;
        for &(child, instances) in &cells[at].children {
            let each = walk(cells, child, depth + 1, memo)?.saturating_add(INSTANCE_BYTES);
            bytes = bytes.saturating_add(each.saturating_mul(instances));
            if bytes > MAX_FLAT_BYTES {
                return Err(FlatSizeError::TooLarge);
            }
        }
        memo[at] = Some(bytes);
        Ok(bytes)
    }
    let bytes = walk(cells, top, 0, &mut vec![None; cells.len()])?;
    if bytes > MAX_FLAT_BYTES {
        return Err(FlatSizeError::TooLarge);
    }
    Ok(bytes)
}

#[cfg(test)]
mod tests {
    use super::*;

    fn cell(own_bytes: usize, children: &[(usize, usize)]) -> CellSize {
        CellSize {
            own_bytes,
            children: children.to_vec(),
        }
    }

    #[test]
    fn a_shared_cell_counts_once_per_instance() {
        // top places leaf 3 times directly and twice through mid (which places it 4 times).
        let cells = [
            cell(10, &[(1, 3), (2, 2)]),
            cell(100, &[]),
            cell(1, &[(1, 4)]),
        ];
        let mid = 1 + 4 * (100 + INSTANCE_BYTES);
        let want = 10 + 3 * (100 + INSTANCE_BYTES) + 2 * (mid + INSTANCE_BYTES);
        assert_eq!(flattened_bytes(&cells, 0), Ok(want));
    }

    #[test]
    fn nested_arrays_are_refused_before_they_expand() {
        // Ten levels of 100×100 arrays: 10^40 instances, a few hundred bytes of file.
        let mut cells: Vec<CellSize> = (0..10).map(|i| cell(0, &[(i + 1, 10_000)])).collect();
        cells.push(cell(polygon_bytes(4), &[]));
        assert_eq!(flattened_bytes(&cells, 0), Err(FlatSizeError::TooLarge));
    }

    #[test]
    fn a_cycle_is_too_deep() {
        let cells = [cell(0, &[(1, 1)]), cell(0, &[(0, 1)])];
        assert_eq!(flattened_bytes(&cells, 0), Err(FlatSizeError::TooDeep));
    }

    #[test]
    fn the_limit_is_inclusive_of_the_instances_held() {
        let n = MAX_FLAT_BYTES / INSTANCE_BYTES;
        assert!(flattened_bytes(&[cell(0, &[(1, n)]), cell(0, &[])], 0).is_ok());
        assert_eq!(
            flattened_bytes(&[cell(0, &[(1, n + 1)]), cell(0, &[])], 0),
            Err(FlatSizeError::TooLarge)
        );
    }
}
