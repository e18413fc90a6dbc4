//! The float types an image plane may be held in. Photos and the planes computed from them are
//! `f64` where precision is cheap and `f32` where a camera-size image must fit in memory (a
//! 16-megapixel RGB plane set is 400 MB in `f64`, 200 MB in `f32`); the arithmetic is `f64`
//! either way and only the storage differs.

/// `f32` or `f64`: a stored image sample.
pub trait Sample:
    Copy
    + Default
    + Send
    + Sync
    + PartialOrd
    + std::fmt::Debug
    + std::fmt::Display
    + Into<f64>
    + 'static
{
    /// The nearest stored value of `v`.
    fn from_f64(v: f64) -> Self;
    /// A plane's `f32` samples in this type; no copy for `f32`.
    fn vec_from_f32(v: Vec<f32>) -> Vec<Self>;
    /// A plane's samples as `f32`, row-major; no copy for an `f32` plane in standard layout.
    fn plane_into_f32(plane: ndarray::Array2<Self>) -> Vec<f32>;
}

impl Sample for f64 {
    fn from_f64(v: f64) -> Self {
        v
    }
    fn vec_from_f32(v: Vec<f32>) -> Vec<Self> {
        v.into_iter().map(f64::from).collect()
    }
    fn plane_into_f32(plane: ndarray::Array2<Self>) -> Vec<f32> {
        plane.iter().map(|&v| v as f32).collect()
    }
}

impl Sample for f32 {
    fn from_f64(v: f64) -> Self {
        v as f32
    }
    fn vec_from_f32(v: Vec<f32>) -> Vec<Self> {
        v
    }
    fn plane_into_f32(plane: ndarray::Array2<Self>) -> Vec<f32> {
        let plane = if plane.is_standard_layout() {
            plane
        } else {
            plane.as_standard_layout().into_owned()
        };
        let len = plane.len();
        let (v, offset) = plane.into_raw_vec_and_offset();
        // An owned plane cut from a larger one keeps the larger one's buffer: take its part.
        let start = offset.unwrap_or(0);
        if start == 0 && v.len() == len {
            v
        } else {
            v[start..start + len].to_vec()
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use ndarray::Array2;

    #[test]
    fn planes_convert_row_major_whatever_their_layout() {
        let a = Array2::from_shape_fn((2, 3), |(y, x)| (y * 3 + x) as f32);
        assert_eq!(f32::plane_into_f32(a.clone()), vec![0., 1., 2., 3., 4., 5.]);
        assert_eq!(
            f32::plane_into_f32(a.t().to_owned()),
            vec![0., 3., 1., 4., 2., 5.]
        );
        assert_eq!(
            f64::plane_into_f32(a.mapv(f64::from).reversed_axes()),
            vec![0., 3., 1., 4., 2., 5.]
        );
        assert_eq!(f64::vec_from_f32(vec![0.5, 2.0]), vec![0.5, 2.0]);
        // The middle row of a 3 × 3 plane, cut in place: its buffer still holds all nine.
        let mut cut = Array2::from_shape_fn((3, 3), |(y, x)| (y * 3 + x) as f32);
        cut.slice_axis_inplace(ndarray::Axis(0), ndarray::Slice::from(1..2));
        assert_eq!(f32::plane_into_f32(cut), vec![3., 4., 5.]);
    }
}
