//! Bindings of the quantum symmetric top: conversion only, the physics stays in the core.

use crate::errors::IntoPyResult;
use kreisel_core::quantum::{ebk, SymmetricTop};
use numpy::{IntoPyArray, PyArray1, PyArray2, PyArrayMethods, PyReadonlyArray1};
use pyo3::prelude::*;

type Arr<'py> = Bound<'py, PyArray1<f64>>;

/// The native quantum symmetric top (I1, I3, hbar; validated by the core).
#[pyclass(name = "SymmetricTop", module = "kreisel._core", frozen)]
pub struct PySymmetricTop {
    inner: SymmetricTop,
}

#[pymethods]
impl PySymmetricTop {
    #[new]
    fn new(py: Python<'_>, i1: f64, i3: f64, hbar: f64) -> PyResult<Self> {
        Ok(PySymmetricTop {
            inner: SymmetricTop::new(i1, i3, hbar).py(py)?,
        })
    }

    /// hbar^2 / (2 I1) (J).
    #[getter]
    fn b(&self) -> f64 {
        self.inner.b()
    }

    /// hbar^2 (1/(2 I3) - 1/(2 I1)) (J).
    #[getter]
    fn k_constant(&self) -> f64 {
        self.inner.k_constant()
    }

    /// Free-rotor energy E(J, K) (J).
    fn free_energy(&self, py: Python<'_>, j: i64, k: i64) -> PyResult<f64> {
        self.inner.free_energy(j, k).py(py)
    }

    /// Eigenvalues of the (K, M) block for every strength: shape (len(strengths), levels).
    fn levels<'py>(
        &self,
        py: Python<'py>,
        k: i64,
        m: i64,
        j_max: i64,
        strengths: PyReadonlyArray1<'py, f64>,
    ) -> PyResult<Bound<'py, PyArray2<f64>>> {
        let p = strengths.as_slice()?.to_vec();
        let top = self.inner;
        let out = py.detach(move || top.levels(k, m, j_max, &p)).py(py)?;
        // The core has checked J_max >= max(|K|, |M|), so the row length is known even for
        // an empty batch.
        let n = (j_max - k.abs().max(m.abs()) + 1) as usize;
        out.into_pyarray(py).reshape([strengths.len()?, n])
    }

    /// (j_min, free energies, <J|cos|J>, <J+1|cos|J>) of the (K, M) block.
    fn block<'py>(
        &self,
        py: Python<'py>,
        k: i64,
        m: i64,
        j_max: i64,
    ) -> PyResult<(i64, Arr<'py>, Arr<'py>, Arr<'py>)> {
        let b = self.inner.block(k, m, j_max).py(py)?;
        Ok((
            b.j_min,
            b.free.into_pyarray(py),
            b.cos_diag.into_pyarray(py),
            b.cos_off.into_pyarray(py),
        ))
    }

    /// Nutation action (J s) of the classical top at `energy` (J).
    fn nutation_action(
        &self,
        py: Python<'_>,
        k: i64,
        m: i64,
        energy: f64,
        strength: f64,
    ) -> PyResult<f64> {
        ebk::nutation_action(&self.inner, k, m, energy, strength).py(py)
    }

    /// EBK energies (J) of the level (K, M, n) at every strength.
    fn ebk_energy<'py>(
        &self,
        py: Python<'py>,
        k: i64,
        m: i64,
        n: i64,
        strengths: PyReadonlyArray1<'py, f64>,
    ) -> PyResult<Arr<'py>> {
        let p = strengths.as_slice()?.to_vec();
        let top = self.inner;
        let out: kreisel_core::Result<Vec<f64>> =
            py.detach(move || p.iter().map(|&s| ebk::energy(&top, k, m, n, s)).collect());
        Ok(out.py(py)?.into_pyarray(py))
    }
}
