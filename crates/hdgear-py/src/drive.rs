//! `hdgear.Drive`: a harmonic drive in SI units, its reduction, simulation and design check.

use crate::convert::{Detection, check_samples, err, to_py, tol};
use crate::params::Params;
use hdgear::physical::PhysicalParams;
use numpy::{IntoPyArray, PyArray1};
use pyo3::exceptions::PyValueError;
use pyo3::prelude::*;
use std::collections::BTreeMap;

/// A drive in SI units (see `hdgear.Drive`).
#[pyclass(frozen, module = "hdgear._hdgear")]
#[derive(Clone)]
pub(crate) struct Drive {
    pub(crate) inner: PhysicalParams,
}

#[pymethods]
impl Drive {
    /// A drive from a dict of all ten values (validated; unknown or missing names refused).
    #[staticmethod]
    fn from_dict(values: BTreeMap<String, f64>) -> PyResult<Drive> {
        let object = values
            .into_iter()
            .map(|(k, v)| (k, serde_json::Value::from(v)))
            .collect::<serde_json::Map<_, _>>();
        let inner: PhysicalParams = serde_json::from_value(object.into())
            .map_err(|e| PyValueError::new_err(format!("invalid drive: {e}")))?;
        inner.validate().map_err(err)?;
        Ok(Drive { inner })
    }

    /// A catalogue drive with the documented assumptions, and the fit: (drive, fit dict).
    #[staticmethod]
    #[pyo3(signature = (name, fit_torque=None))]
    fn catalogue<'py>(
        py: Python<'py>,
        name: &str,
        fit_torque: Option<f64>,
    ) -> PyResult<(Drive, Bound<'py, PyAny>)> {
        let (inner, fit) = hdgear::physical::catalogue::preset(name, fit_torque).map_err(err)?;
        Ok((Drive { inner }, to_py(py, &fit)?))
    }

    /// The ten values as a dict.
    fn to_dict<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyAny>> {
        to_py(py, &self.inner)
    }

    /// The reduction to the dimensionless model: (Params, reduction dict).
    fn reduce<'py>(&self, py: Python<'py>) -> PyResult<(Params, Bound<'py, PyAny>)> {
        let r = self.inner.reduce().map_err(err)?;
        Ok((Params { inner: r.params }, to_py(py, &r)?))
    }

    /// The two-inertia simulation from rest: (t, theta_in, theta_out, theta, theta_dot, summary).
    #[pyo3(signature = (t_end, dt, rtol, atol))]
    #[allow(clippy::type_complexity)]
    fn simulate<'py>(
        &self,
        py: Python<'py>,
        t_end: f64,
        dt: f64,
        rtol: f64,
        atol: f64,
    ) -> PyResult<(Vec<Bound<'py, PyArray1<f64>>>, Bound<'py, PyAny>)> {
        let d = self.inner;
        let t = tol(rtol, atol, "taylor")?;
        check_samples(t_end, dt)?;
        let (cols, s) = py
            .detach(|| {
                let mut cols: [Vec<f64>; 5] = Default::default();
                hdgear::physical::simulate::simulate_physical(&d, t_end, dt, t, |s| {
                    for (c, v) in
                        cols.iter_mut()
                            .zip([s.t, s.theta_in, s.theta_out, s.theta, s.theta_dot])
                    {
                        c.push(v);
                    }
                })
                .map(|s| (cols, s))
            })
            .map_err(err)?;
        Ok((
            cols.into_iter().map(|c| c.into_pyarray(py)).collect(),
            to_py(py, &s.report())?,
        ))
    }

    /// The torque across the compliance [N m] at the twist θ [rad] and its rate θ' [rad/s]: the
    /// drive's spring with its backlash, and its damping (`Physical::twist_torque`).
    fn twist_torque(&self, theta: f64, theta_dot: f64) -> f64 {
        hdgear::physical::model::Physical::new(self.inner).twist_torque(theta, theta_dot)
    }

    /// The design check as a dict.
    #[pyo3(signature = (detection))]
    fn design_check<'py>(
        &self,
        py: Python<'py>,
        detection: Detection,
    ) -> PyResult<Bound<'py, PyAny>> {
        let d = self.inner;
        let opts = detection.0;
        let c = py
            .detach(|| hdgear::physical::design::design_check(&d, &opts))
            .map_err(err)?;
        to_py(py, &c)
    }
}

/// A bearing's friction law in SI units (see `hdgear.mujoco.DriveJoint`).
#[pyclass(frozen, module = "hdgear._hdgear")]
pub(crate) struct Bearing {
    law: hdgear::physical::model::Bearings,
}

#[pymethods]
impl Bearing {
    /// The law `LAW:KEY=VALUE,…` on `side` (`output` or `input`), as the CLI's
    /// `--output-bearing` takes it (`friction` or `stribeck`, every key given).
    #[new]
    fn new(side: &str, text: &str) -> PyResult<Bearing> {
        use hdgear::physical::model::Bearings;
        let law = Bearings::parse_law(side, text).map_err(err)?;
        Ok(Bearing {
            law: Bearings::new(Some(law), None).map_err(err)?,
        })
    }

    /// The friction torque [N m] at the rate [rad/s], opposing it.
    fn torque(&self, rate: f64) -> f64 {
        self.law.torques(rate, 0.0)[0]
    }
}
