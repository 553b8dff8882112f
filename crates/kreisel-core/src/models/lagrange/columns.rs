//! The columns that plots of an exact Lagrange motion need, from its angles and rates: the
//! energy, Mz, M3 and the potential m g l cos(theta), evaluated as [`LagrangeTop::invariants`]
//! does (so their drift shows the solution's accuracy, not a second formula's).

use super::{EulerState, LagrangeTop};

/// Energy (J), Mz, M3 (kg m^2/s) and potential (J) at each row.
#[derive(Debug, Clone, Default, PartialEq)]
pub struct LagrangeColumns {
    /// Energy.
    pub energy: Vec<f64>,
    /// Vertical angular momentum.
    pub mz: Vec<f64>,
    /// Axial angular momentum.
    pub m3: Vec<f64>,
    /// m g l cos(theta).
    pub potential: Vec<f64>,
}

impl LagrangeTop {
    /// The invariants and the potential at each (theta, theta_dot, phi_dot, psi_dot) row
    /// (slices of one length; the shortest sets the rows).
    pub fn columns(
        &self,
        theta: &[f64],
        theta_dot: &[f64],
        phi_dot: &[f64],
        psi_dot: &[f64],
    ) -> LagrangeColumns {
        let n = theta
            .len()
            .min(theta_dot.len())
            .min(phi_dot.len())
            .min(psi_dot.len());
        let mut c = LagrangeColumns {
            energy: Vec::with_capacity(n),
            mz: Vec::with_capacity(n),
            m3: Vec::with_capacity(n),
            potential: Vec::with_capacity(n),
        };
        for i in 0..n {
            let s = EulerState {
                theta: theta[i],
                phi: 0.0,
                psi: 0.0,
                theta_dot: theta_dot[i],
                phi_dot: phi_dot[i],
                psi_dot: psi_dot[i],
            };
            let inv = self.invariants(&s);
            c.energy.push(inv.energy);
            c.mz.push(inv.mz);
            c.m3.push(inv.m3);
            c.potential.push(self.mgl() * theta[i].cos());
        }
        c
    }
}
