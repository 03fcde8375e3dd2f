//! The joint-space spline through waypoints, its storage on the heap: the core's
//! interpolating periodic B-spline ([`spline_through`], evaluated by [`SplineView`]), with
//! its control points in vectors of the waypoints' number. The core's `PeriodicBSpline` keeps
//! a fixed capacity inline, so a capacity of [`MAX_WAYPOINTS`](super::MAX_WAYPOINTS) would be
//! built on the stack (about 105 KB for six joints) and pass through every function that
//! builds, clones or converts a controller; here only three vectors do.

use crate::error::Result;
use pvfc_core::contour::{spline_through, ContourSample, SplineView};
use pvfc_core::prelude::*;

/// A closed C² curve through `n ≥ 3` joint-space waypoints, one every `spacing` of `τ`: the
/// same curve, to the bit, as `PeriodicBSpline::through_slice` on the same waypoints.
#[derive(Clone, Debug, PartialEq)]
pub struct WaypointSpline<const N: usize> {
    control: Vec<JointSpace<f64, N>>,
    delta: Vec<Tangent<f64, N>>,
    spacing: f64,
}

impl<const N: usize> WaypointSpline<N> {
    /// The interpolating spline through `waypoints` at `τ = k·spacing` (the core's errors: too
    /// few points, a bad spacing, non-finite points, waypoints too coarse).
    pub fn through(waypoints: &[JointSpace<f64, N>], spacing: f64) -> Result<Self> {
        let n = waypoints.len();
        let mut control = vec![JointSpace::identity(); n];
        let mut delta = vec![Tangent::<f64, N>::zeros(); n];
        let mut next = vec![JointSpace::identity(); n];
        spline_through(waypoints, spacing, &mut control, &mut delta, &mut next)?;
        Ok(WaypointSpline {
            control,
            delta,
            spacing,
        })
    }

    /// The control points.
    pub fn control_points(&self) -> &[JointSpace<f64, N>] {
        &self.control
    }

    /// The spacing of the knots in `τ`.
    pub fn spacing(&self) -> f64 {
        self.spacing
    }
}

impl<const N: usize> Contour<f64, JointSpace<f64, N>, N> for WaypointSpline<N> {
    #[inline]
    fn sample(&self, tau: f64) -> ContourSample<f64, JointSpace<f64, N>, N> {
        SplineView::new(&self.control, &self.delta, self.spacing).sample(tau)
    }

    fn period(&self) -> Option<f64> {
        Some(self.spacing * self.control.len() as f64)
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use nalgebra::SVector;

    /// The heap spline is the core's `PeriodicBSpline` to the bit: the same control points and
    /// the same samples (point, velocity, acceleration) along two periods, negative `τ` too.
    #[test]
    fn it_is_the_core_spline_to_the_bit() -> Result<()> {
        let kinds = [
            JointKind::Circular,
            JointKind::Circular,
            JointKind::Linear,
            JointKind::Circular,
        ];
        let waypoints: Vec<JointSpace<f64, 4>> = [
            [0.0, -1.2, 0.1, 0.3],
            [0.4, -1.0, 0.3, -0.2],
            [0.1, -0.6, 0.2, 0.5],
            [-0.3, -0.9, 0.0, 0.1],
            [-0.2, -1.4, 0.15, -0.4],
        ]
        .iter()
        .map(|w| JointSpace::new(SVector::from_column_slice(w), kinds))
        .collect();
        let heap = WaypointSpline::through(&waypoints, 1.7)?;
        let core =
            PeriodicBSpline::<f64, JointSpace<f64, 4>, 4, 64>::through_slice(&waypoints, 1.7)?;
        assert_eq!(heap.control_points(), core.control_points());
        assert_eq!(heap.period(), core.period());
        for k in -170..=170 {
            let tau = 0.1 * k as f64 + 0.013;
            assert_eq!(heap.sample(tau), core.sample(tau), "τ = {tau}");
        }
        // The core's errors, through the sim's error type.
        assert!(WaypointSpline::through(&waypoints[..2], 1.7).is_err());
        assert!(WaypointSpline::through(&waypoints, 0.0).is_err());
        Ok(())
    }
}
