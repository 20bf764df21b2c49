//! The report's (ω, δ) plane at the study's γ: the fold curves of the frequency response with
//! their cusps (two-parameter continuation), the period-doubling curves when there are any, and
//! the bursting boundary (predicted and simulated) with the fold set and the fast-slow edge.

use crate::burst::{BoundaryKind, BurstOptions, PlaneCurve, PlaneOptions, plane_boundaries};
use crate::error::{Error, Result};
use crate::output::plot::Figure;
use crate::params::{Param, Params};
use crate::periodic::{
    Box2, Codim2, ContinuationOptions, Curve2, CurveKind, Range, curves_from_branch,
};
use serde::Serialize;

/// The continuation ranges of the fold and period-doubling curves: the first parameter's range
/// holds the frequency response's folds at the study's δ.
pub const CURVE_RANGES: [&str; 2] = ["omega=0.3:20:log", "delta=0.5:40:log"];

/// The box of the boundaries: the same δ, ω down to 1e-4 (the bursting boundary).
pub const BOUNDARY_RANGES: [&str; 2] = ["omega=1e-4:20:log", "delta=0.5:40:log"];

/// The plane's curves.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct PlaneEvidence {
    /// The fold curves.
    pub folds: Vec<Curve2<Param>>,
    /// The period-doubling curves (none when the one-parameter branch has no doubling).
    pub doublings: Vec<Curve2<Param>>,
    /// The boundaries, every kind.
    pub boundaries: Vec<PlaneCurve>,
}

impl PlaneEvidence {
    /// Computes the plane at `base`'s γ and other parameters.
    pub fn compute(base: &Params, burst: &BurstOptions) -> Result<PlaneEvidence> {
        let parse = |specs: [&str; 2]| -> Result<[Range; 2]> {
            Ok([Range::parse(specs[0])?, Range::parse(specs[1])?])
        };
        let curves = parse(CURVE_RANGES)?;
        let opts = ContinuationOptions::default();
        let follow = |kind| match curves_from_branch(base, curves, kind, None, 1, &opts) {
            // no special point of this kind on the branch: no curve
            Err(Error::InvalidInput { what: "start", .. }) => Ok(Vec::new()),
            other => other,
        };
        let folds = follow(CurveKind::Fold)?;
        let doublings = follow(CurveKind::PeriodDoubling)?;
        let ranges = parse(BOUNDARY_RANGES)?;
        let boundaries = plane_boundaries(
            base,
            ranges.map(|r| r.param),
            &Box2::of(ranges),
            &BoundaryKind::ALL,
            &PlaneOptions::default(),
            burst,
        )?;
        Ok(PlaneEvidence {
            folds,
            doublings,
            boundaries,
        })
    }

    /// The figure: every curve in the (ω, δ) plane, log-log.
    pub fn figure(&self) -> Figure {
        let mut curves = self.folds.clone();
        curves.extend(self.doublings.iter().cloned());
        crate::figures::plane_figure(
            &curves,
            &self.boundaries,
            [Param::Omega.name(), Param::Delta.name()],
            [true, true],
        )
    }

    /// The cusps of the fold curves, (ω, δ).
    pub fn cusps(&self) -> Vec<[f64; 2]> {
        self.folds
            .iter()
            .flat_map(|c| c.points.iter())
            .filter(|q| q.special == Some(Codim2::Cusp))
            .map(|q| q.params)
            .collect()
    }

    /// The boundary of `kind` at δ = `delta`: ω where its first curve crosses that δ (linear
    /// interpolation in log scale between its points), if it does.
    pub fn omega_at(&self, kind: BoundaryKind, delta: f64) -> Option<f64> {
        let c = self.boundaries.iter().find(|c| c.kind == kind)?;
        c.points.windows(2).find_map(|w| {
            let (a, b) = (w[0].params, w[1].params);
            let (la, lb, l) = (a[1].ln(), b[1].ln(), delta.ln());
            if (la - l) * (lb - l) > 0.0 || la == lb {
                return None;
            }
            let t = (l - la) / (lb - la);
            Some((a[0].ln() + t * (b[0].ln() - a[0].ln())).exp())
        })
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// `omega_at` interpolates between the two points around δ, in log scale.
    #[test]
    fn omega_at_interpolates_in_log_scale() {
        let q = |w: f64, d: f64| crate::burst::PlanePoint {
            params: [w, d],
            outside: [w, d],
            inside: [w, d],
        };
        let e = PlaneEvidence {
            folds: Vec::new(),
            doublings: Vec::new(),
            boundaries: vec![PlaneCurve {
                kind: BoundaryKind::Predicted,
                params: [Param::Omega, Param::Delta],
                points: vec![q(1e-3, 1.0), q(1e-2, 100.0)],
                end: crate::burst::PlaneEnd::Edge,
                evaluations: 0,
            }],
        };
        let w = e.omega_at(BoundaryKind::Predicted, 10.0).unwrap();
        assert!((w / 10f64.powf(-2.5) - 1.0).abs() < 1e-12);
        assert_eq!(e.omega_at(BoundaryKind::Predicted, 1e3), None);
        assert_eq!(e.omega_at(BoundaryKind::Simulated, 10.0), None);
    }
}
