//! The error budget of a conversion, and the warning given when a measured error is far
//! above it.
//!
//! The budget is the fitter's own: half a displacement step may reach
//! `max_step_error × spacing` (a tenth of the node spacing by default) before a patch gets a
//! finer step. A faithful conversion keeps most of the source surface within that distance
//! of its patches; what lies farther is surface the patches missed or misplaced (faces wound
//! against their neighbours, parts thinner than the lattice, layers the rays did not reach).
//!
//! The check reads the 95th percentile of the source-to-patch distances (the evaluator's
//! `surface_to_patch.p95`): the maximum is dominated by single crease corners even on clean
//! models, the RMS by the few far samples, and the 95th percentile moves only when a real
//! share of the surface is off. Measured with default options (p95 over the budget): bunny
//! 0.38, fandisk 0.90, cylinder 0.16; a cube with every other triangle flipped and its
//! winding kept (`--keep-winding`) 3.9. The
//! warning starts at [`FAR_ABOVE_BUDGET`] times the budget.
//!
//! Cost: O(1) on figures already measured.

use std::fmt;

/// How many times its budget the 95th percentile of the source-to-patch distance may reach
/// before [`check_error_budget`] warns.
pub const FAR_ABOVE_BUDGET: f64 = 2.5;

/// A conversion whose measured error is far above its budget.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct ErrorBudgetWarning {
    /// The 95th percentile of the source-to-patch distance (model units).
    pub p95: f64,
    /// The budget: `max_step_error × spacing` (model units).
    pub budget: f64,
    /// The node spacing (model units).
    pub spacing: f64,
    /// The fitter's `max_step_error`: the budget as a fraction of the spacing.
    pub max_step_error: f64,
}

impl fmt::Display for ErrorBudgetWarning {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(
            f,
            "5 % of the source surface is more than {:.3e} from the patches, {:.1} times the \
             error budget ({:.3e} = {} x the node spacing {:.3e}): look for faces wound \
             against their neighbours, or parts thinner than the spacing (--spacing)",
            self.p95,
            self.p95 / self.budget,
            self.budget,
            self.max_step_error,
            self.spacing
        )
    }
}

/// The warning for a conversion at node `spacing` with the fitter's `max_step_error` (a
/// fraction of the spacing) whose source-to-patch distances have the 95th percentile `p95`,
/// when that is more than [`FAR_ABOVE_BUDGET`] times the budget; `None` otherwise, and when
/// a figure is not finite or positive.
pub fn check_error_budget(
    spacing: f32,
    max_step_error: f32,
    p95: f64,
) -> Option<ErrorBudgetWarning> {
    let spacing = f64::from(spacing);
    let budget = f64::from(max_step_error) * spacing;
    let valid = budget.is_finite() && budget > 0.0 && p95.is_finite();
    (valid && p95 > FAR_ABOVE_BUDGET * budget).then_some(ErrorBudgetWarning {
        p95,
        budget,
        spacing,
        max_step_error: f64::from(max_step_error),
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn warns_only_far_above_the_budget() {
        assert_eq!(check_error_budget(1.0, 0.1, 0.2), None);
        let w = check_error_budget(1.0, 0.1, 0.4).unwrap();
        assert!((w.p95 / w.budget - 4.0).abs() < 1e-6);
        assert!(w.to_string().contains("4.0 times"));
        assert_eq!(check_error_budget(1.0, 0.1, f64::INFINITY), None);
        assert_eq!(check_error_budget(0.0, 0.1, 1.0), None);
    }
}
