//! The heavy top as first-order systems for the general-purpose integrators: in
//! y = (q, omega) for the explicit methods, in y = (q, M) for the implicit Gauss methods.

use super::{HeavyTop, RigidState};
use crate::integrate::OdeSystem;
use crate::rotation::{cross, Quat};

/// The heavy top in y = (q, omega); `AXIAL` (only for a top that is [`HeavyTop::axial`])
/// evaluates the right-hand side without its vanishing terms.
pub struct QOmega<'a, const AXIAL: bool>(pub &'a HeavyTop);

impl<const AXIAL: bool> OdeSystem<7> for QOmega<'_, AXIAL> {
    #[inline(always)]
    fn rhs(&self, _t: f64, y: &[f64; 7], dy: &mut [f64; 7]) {
        if AXIAL {
            self.0.rhs_axial(y, dy);
        } else {
            self.0.rhs(y, dy);
        }
    }
    fn project(&self, y: &mut [f64; 7]) {
        normalize_quaternion(y);
    }
}

/// The heavy top in y = (q, M). With Gamma = q* ez q quadratic in q, the energy
/// `M.I^-1 M / 2 + m g c.Gamma(q)` and `|q|^2` are quadratic invariants, which the implicit
/// Gauss methods keep exactly (Mz = M.Gamma is cubic: kept to the method's accuracy).
pub struct QM<'a>(pub &'a HeavyTop);

impl OdeSystem<7> for QM<'_> {
    fn rhs(&self, _t: f64, y: &[f64; 7], dy: &mut [f64; 7]) {
        let top = self.0;
        let q = Quat([y[0], y[1], y[2], y[3]]);
        let m = [y[4], y[5], y[6]];
        let w = top.omega(m);
        let dq = q.hamilton(Quat([0.0, w[0], w[1], w[2]]));
        let dm = cross(m, w);
        let tq = cross(q.up_in_body(), top.mgc());
        for (d, x) in dy.iter_mut().zip(dq.0) {
            *d = 0.5 * x;
        }
        for i in 0..3 {
            dy[4 + i] = dm[i] + tq[i];
        }
    }
}

/// Scales the quaternion in the first four components of `y` to unit length.
#[inline(always)]
pub fn normalize_quaternion(y: &mut [f64]) {
    let n = (y[0] * y[0] + y[1] * y[1] + y[2] * y[2] + y[3] * y[3]).sqrt();
    for v in y.iter_mut().take(4) {
        *v /= n;
    }
}

/// y = (q, omega) of a state.
pub fn pack(s: &RigidState) -> [f64; 7] {
    let q = s.q.0;
    [q[0], q[1], q[2], q[3], s.omega[0], s.omega[1], s.omega[2]]
}

/// The state of y = (q, omega), the quaternion normalised.
pub fn unpack(y: &[f64; 7]) -> RigidState {
    RigidState {
        q: Quat([y[0], y[1], y[2], y[3]]).normalized(),
        omega: [y[4], y[5], y[6]],
    }
}
