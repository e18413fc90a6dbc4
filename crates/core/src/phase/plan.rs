//! The folding-wavelength plans a user names (`--lambda0 fixed:530 | uniform | optimized`):
//! the two that are a [`Lambda0`] at once, and the optimizer's, which becomes one only after
//! the allocation has run.

use super::Lambda0;

/// A λ0 plan by name.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Lambda0Plan {
    /// Every lenslet folded at one wavelength, nm.
    Fixed(f64),
    /// The 400–700 nm grid in equal counts.
    Uniform,
    /// Algorithm 1's allocation for the design (run first).
    Optimized,
}

impl Lambda0Plan {
    /// Reads `fixed:NM`, `uniform` or `optimized` (any case).
    ///
    /// # Errors
    /// Anything else, or a wavelength that is not a number, said in words (the caller names
    /// the flag or field).
    pub fn parse(text: &str) -> Result<Lambda0Plan, String> {
        let t = text.trim().to_ascii_lowercase();
        match t.as_str() {
            "uniform" => return Ok(Lambda0Plan::Uniform),
            "optimized" => return Ok(Lambda0Plan::Optimized),
            _ => {}
        }
        if let Some(v) = t.strip_prefix("fixed:") {
            return v
                .trim()
                .parse()
                .map(Lambda0Plan::Fixed)
                .map_err(|_| format!("`{v}` is not a wavelength in nm"));
        }
        Err("expected fixed:NM (e.g. fixed:530), uniform or optimized".into())
    }

    /// Its spelling on the command line (`fixed:530`).
    pub fn as_arg(self) -> String {
        match self {
            Lambda0Plan::Fixed(nm) => format!("fixed:{nm}"),
            Lambda0Plan::Uniform => "uniform".into(),
            Lambda0Plan::Optimized => "optimized".into(),
        }
    }

    /// The plan a design's λ0 is, where it has a name (a fixed or the uniform plan); the
    /// optimizer's counts and hand-edited λ0 have none.
    pub fn of(lambda0: &Lambda0) -> Option<Lambda0Plan> {
        match lambda0 {
            Lambda0::Fixed { nm } => Some(Lambda0Plan::Fixed(*nm)),
            Lambda0::Uniform => Some(Lambda0Plan::Uniform),
            Lambda0::Counts { .. } | Lambda0::PerLenslet { .. } => None,
        }
    }

    /// The λ0 it is without running anything; `None` for [`Lambda0Plan::Optimized`].
    pub fn lambda0(self) -> Option<Lambda0> {
        match self {
            Lambda0Plan::Fixed(nm) => Some(Lambda0::Fixed { nm }),
            Lambda0Plan::Uniform => Some(Lambda0::Uniform),
            Lambda0Plan::Optimized => None,
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn plans_read_back_as_they_are_written() {
        for p in [
            Lambda0Plan::Fixed(530.0),
            Lambda0Plan::Fixed(612.5),
            Lambda0Plan::Uniform,
            Lambda0Plan::Optimized,
        ] {
            assert_eq!(Lambda0Plan::parse(&p.as_arg()), Ok(p));
        }
        assert_eq!(
            Lambda0Plan::parse(" Fixed:600 "),
            Ok(Lambda0Plan::Fixed(600.0))
        );
        for bad in ["", "fixed:", "fixed:green", "best"] {
            assert!(Lambda0Plan::parse(bad).is_err(), "{bad:?}");
        }
        assert_eq!(Lambda0Plan::of(&Lambda0::Counts { counts: vec![1] }), None);
        assert_eq!(Lambda0Plan::Optimized.lambda0(), None);
    }
}
