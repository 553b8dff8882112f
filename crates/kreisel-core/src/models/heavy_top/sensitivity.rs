//! Forward sensitivities of the heavy top on a fixed pivot (undamped, or with viscous and
//! drag torques at it): the derivatives of a run with respect to the top's parameters and its
//! initial state, integrated with the run by DOP853 (theory: sensitivities).
//!
//! For `y' = f(y, p)`, `y(0) = y0(p)`, the sensitivity `S = dy/dp` obeys the variational
//! equation `S' = (df/dy) S + df/dp`, `S(0) = dy0/dp` (Hairer, Norsett & Wanner, *Solving
//! Ordinary Differential Equations I*, Sec. I.14). The orientation lives on the rotation
//! group, so it is perturbed through the exponential map, in the body frame:
//! `R(p + dp) = R(p) exp([xi dp]x)`, `q -> q exp(xi dp / 2)`: its sensitivity `xi` has three
//! components, not the four of a quaternion. With `R' = R [omega]x` and `Gamma = R^T e_z`:
//!
//! `xi' = xi x omega + d_omega`,
//! `I d_omega' = (I d_omega) x omega + (I omega) x d_omega + (Gamma x xi) x (m g c) + b_p`,
//!
//! where `b_p` is the explicit derivative of Euler's equations `I omega' = (I omega) x omega +
//! Gamma x (m g c)` in the parameter: for a principal moment `I_k`,
//! `b = (omega_k e_k) x omega - omega'_k e_k`; for m, g and `c_k`, `Gamma x` the derivative
//! of `m g c`; a damping torque `-(c + k |omega|) omega` adds its tangent
//! `-(c + k |omega|) d_omega - k (omega . d_omega / |omega|) omega`, and its coefficients
//! `-omega` and `-|omega| omega`. The Jacobians are written out here, not differenced.
//!
//! The trajectory is the one a plain run takes, bit for bit: the sensitivities ride on its
//! steps and are left out of the step-size control (see [`Sensitivities::control`] and the
//! theory page for the measurements behind that choice).

use super::driven::{DrivenRow, DrivenTop, Pivot, DIM};
use super::equations::{pack, unpack, QOmega};
use super::{HeavyTop, RigidState};
use crate::error::{KreiselError, Result};
use crate::integrate::{OdeSystem, Stream};
use crate::rotation::{cross, dot, Quat};
use crate::simulate::{self, integrate_error, Model, RunInfo, Settings, Stats, Status, MAX_ROWS};

/// The parameters of a [`HeavyTop`] that have sensitivities, by their public names.
pub const HEAVY_PARAMETERS: [&str; 8] = ["I1", "I2", "I3", "m", "g", "com[0]", "com[1]", "com[2]"];
/// The parameters of a Lagrange top (`I1 == I2`, `c = (0, 0, l)`): "I1" moves both
/// transverse moments.
pub const LAGRANGE_PARAMETERS: [&str; 5] = ["I1", "I3", "m", "l", "g"];
/// The coefficients of the torque at a fixed pivot, `-(viscous + drag |omega|) omega`, of a
/// damped top (without dry friction).
pub const DAMPING_PARAMETERS: [&str; 2] = ["viscous", "drag"];
/// The fields of a state in Euler angles.
pub const EULER_FIELDS: [&str; 6] = ["theta", "phi", "psi", "theta_dot", "phi_dot", "psi_dot"];
/// The fields of a state as (orientation, body rates): the orientation's body-frame
/// rotation vector at t = 0 and the body rates.
pub const RIGID_FIELDS: [&str; 6] = [
    "orientation[0]",
    "orientation[1]",
    "orientation[2]",
    "omega[0]",
    "omega[1]",
    "omega[2]",
];

/// What a sensitivity is taken with respect to.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Param {
    /// A principal moment `I_k` about the pivot (k = 0, 1, 2).
    Inertia(usize),
    /// Both transverse moments at once (a Lagrange top's I1).
    Transverse,
    /// The mass.
    Mass,
    /// The gravitational acceleration.
    Gravity,
    /// A component of the centre of mass (body frame).
    Com(usize),
    /// The viscous coefficient of the torque at the pivot.
    Viscous,
    /// The drag coefficient of the torque at the pivot.
    Drag,
    /// The initial state: the body-frame rotation vector and body rates it moves,
    /// `(xi, d_omega)` at t = 0.
    Initial([f64; 6]),
}

/// The sensitivities a run carries: what each is taken with respect to, by name.
#[derive(Debug, Clone, PartialEq)]
pub struct Sensitivities {
    /// The public names, in the caller's order.
    pub names: Vec<String>,
    /// What each name is.
    pub params: Vec<Param>,
    /// Whether DOP853's step-size control measures the sensitivities too. Off by default:
    /// the run then takes the steps of a plain run, and the sensitivities are accurate to
    /// 10 to 40 times rtol, far better than differences of plain runs at the same tolerance
    /// (theory: sensitivities).
    pub control: bool,
}

/// The largest number of sensitivities a run carries (every parameter of a damped heavy top
/// and every field of its state).
pub const MAX_SENSITIVITIES: usize =
    HEAVY_PARAMETERS.len() + DAMPING_PARAMETERS.len() + EULER_FIELDS.len();

impl Sensitivities {
    /// The sensitivities of `names`: parameters of a heavy top (or of a Lagrange top when
    /// `lagrange`; with [`DAMPING_PARAMETERS`] when `damped`), and fields of the initial
    /// state: of an Euler-angle state `(theta, phi, psi, theta_dot, phi_dot, psi_dot)` when
    /// `euler` is given, else of a state as (quaternion, omega). An unknown or repeated name
    /// is an error naming it and the allowed ones.
    pub fn new(
        names: &[String],
        lagrange: bool,
        damped: bool,
        euler: Option<[f64; 6]>,
    ) -> Result<Self> {
        let mut params: Vec<&str> = if lagrange {
            LAGRANGE_PARAMETERS.to_vec()
        } else {
            HEAVY_PARAMETERS.to_vec()
        };
        if damped {
            params.extend(DAMPING_PARAMETERS);
        }
        let fields: &[&str] = if euler.is_some() {
            &EULER_FIELDS
        } else {
            &RIGID_FIELDS
        };
        let mut out = Vec::with_capacity(names.len());
        for (i, name) in names.iter().enumerate() {
            if names[..i].contains(name) {
                return Err(KreiselError::InvalidParameter {
                    name: "sensitivities".into(),
                    value: format!("{name:?}"),
                    allowed: "each name at most once".into(),
                });
            }
            let p = if let Some(j) = DAMPING_PARAMETERS.iter().position(|p| p == name) {
                if !damped {
                    return Err(KreiselError::InvalidParameter {
                        name: "sensitivities".into(),
                        value: format!("{name:?}"),
                        allowed: "a damping coefficient has a sensitivity where the top is \
                                  given damping=PivotDamping(...)"
                            .into(),
                    });
                }
                [Param::Viscous, Param::Drag][j]
            } else if let Some(j) = params.iter().position(|p| p == name) {
                if lagrange {
                    [
                        Param::Transverse,
                        Param::Inertia(2),
                        Param::Mass,
                        Param::Com(2),
                        Param::Gravity,
                    ][j]
                } else {
                    [
                        Param::Inertia(0),
                        Param::Inertia(1),
                        Param::Inertia(2),
                        Param::Mass,
                        Param::Gravity,
                        Param::Com(0),
                        Param::Com(1),
                        Param::Com(2),
                    ][j]
                }
            } else if let Some(j) = fields.iter().position(|f| f == name) {
                Param::Initial(match euler {
                    Some(e) => euler_initial(e, j),
                    None => {
                        let mut v = [0.0; 6];
                        v[j] = 1.0;
                        v
                    }
                })
            } else {
                return Err(KreiselError::InvalidParameter {
                    name: "sensitivities".into(),
                    value: format!("{name:?}"),
                    allowed: format!(
                        "the {} has the parameters {} and its {} state the fields {}",
                        if lagrange {
                            "Lagrange top"
                        } else {
                            "heavy top"
                        },
                        params.join(", "),
                        if euler.is_some() {
                            "Euler-angle"
                        } else {
                            "(quaternion, omega)"
                        },
                        fields.join(", ")
                    ),
                });
            };
            out.push(p);
        }
        if out.is_empty() {
            return Err(KreiselError::InvalidParameter {
                name: "sensitivities".into(),
                value: "[]".into(),
                allowed: "name at least one parameter or field of the state (or give None)".into(),
            });
        }
        Ok(Sensitivities {
            names: names.to_vec(),
            params: out,
            control: false,
        })
    }
}

/// The error for a model that has no sensitivities yet: `floor` for a top on a floor, else
/// a top on a moving pivot or with dry friction at it.
pub fn unavailable(floor: bool) -> KreiselError {
    KreiselError::InvalidParameter {
        name: "sensitivities".into(),
        value: "a list of names".into(),
        allowed: if floor {
            "sensitivities of tops on a floor are not available yet".into()
        } else {
            "sensitivities are available for a top on a fixed pivot, undamped or with viscous \
             and drag damping; a moving pivot and dry friction at the pivot have none yet"
                .into()
        },
    }
}

/// `(xi, d_omega)` at t = 0 of a derivative in field `j` of an Euler-angle state
/// `(theta, phi, psi, theta_dot, phi_dot, psi_dot)`, z-x-z (`R = Rz(phi) Rx(theta)
/// Rz(psi)`): `Rz(phi) Rx(theta + d) Rz(psi) = R exp(d [Rz(-psi) e_x]x)` and
/// `Rz(phi + d) R = R exp(d [R^T e_z]x)`; the body rates are Goldstein's
/// `omega = (phi' st sp + theta' cp, phi' st cp - theta' sp, phi' ct + psi')`.
pub fn euler_initial(e: [f64; 6], j: usize) -> [f64; 6] {
    let [theta, _phi, psi, theta_dot, phi_dot, _psi_dot] = e;
    let (st, ct) = theta.sin_cos();
    let (sp, cp) = psi.sin_cos();
    match j {
        0 => [
            cp,
            -sp,
            0.0,
            phi_dot * ct * sp,
            phi_dot * ct * cp,
            -phi_dot * st,
        ],
        1 => [st * sp, st * cp, ct, 0.0, 0.0, 0.0],
        2 => [
            0.0,
            0.0,
            1.0,
            phi_dot * st * cp - theta_dot * sp,
            -phi_dot * st * sp - theta_dot * cp,
            0.0,
        ],
        3 => [0.0, 0.0, 0.0, cp, -sp, 0.0],
        4 => [0.0, 0.0, 0.0, st * sp, st * cp, ct],
        _ => [0.0, 0.0, 0.0, 0.0, 0.0, 1.0],
    }
}

/// The derivatives `(theta, phi, psi)` of the z-x-z Euler angles of `q` along the body-frame
/// rotation `xi` (the inverse of the Goldstein relation between Euler rates and body
/// rates); phi's and psi's are infinite where theta = 0 or pi, where they are undefined.
pub fn euler_derivative(q: Quat, xi: [f64; 3]) -> [f64; 3] {
    let (_, theta, psi) = crate::rotation::euler_from_quaternion(q);
    let (st, ct) = theta.sin_cos();
    let (sp, cp) = psi.sin_cos();
    let d_theta = xi[0] * cp - xi[1] * sp;
    let d_phi = (xi[0] * sp + xi[1] * cp) / st;
    [d_theta, d_phi, xi[2] - ct * d_phi]
}

impl HeavyTop {
    /// The tangent of the right-hand side along `(xi, d_omega)` at the state with body
    /// rates `omega`, angular momentum `mom = I omega` and vertical `gamma` (in the body
    /// frame): `(xi', d_omega')` without the parameter's own term (`(df/dy) S` of the
    /// variational equation).
    #[inline(always)]
    pub fn tangent(
        &self,
        gamma: [f64; 3],
        omega: [f64; 3],
        mom: [f64; 3],
        v: &[f64; 6],
    ) -> [f64; 6] {
        let xi = [v[0], v[1], v[2]];
        let dw = [v[3], v[4], v[5]];
        let dxi = cross(xi, omega);
        let dmom = self.momentum(dw);
        let a = cross(dmom, omega);
        let b = cross(mom, dw);
        let dgamma = cross(gamma, xi);
        let c = cross(dgamma, self.mgc());
        let inv = self.inv_inertia;
        [
            dxi[0] + dw[0],
            dxi[1] + dw[1],
            dxi[2] + dw[2],
            (a[0] + b[0] + c[0]) * inv[0],
            (a[1] + b[1] + c[1]) * inv[1],
            (a[2] + b[2] + c[2]) * inv[2],
        ]
    }

    /// The explicit derivative of the body rates' right-hand side in a parameter (`df/dp`
    /// of the variational equation; zero for the initial state and for the orientation), at
    /// the state with vertical `gamma` (body frame), body rates `omega` and their rates
    /// `omega_dot`.
    #[inline(always)]
    pub fn rate_derivative(
        &self,
        p: &Param,
        gamma: [f64; 3],
        omega: [f64; 3],
        omega_dot: [f64; 3],
    ) -> [f64; 3] {
        let inv = self.inv_inertia;
        // I_k: (dI omega) x omega - dI omega', dI = e_k e_k^T.
        let moment = |k: usize| {
            let mut e = [0.0; 3];
            e[k] = omega[k];
            let mut r = cross(e, omega);
            r[k] -= omega_dot[k];
            r
        };
        let torque = |dmgc: [f64; 3]| cross(gamma, dmgc);
        let r = match *p {
            Param::Inertia(k) => moment(k),
            Param::Transverse => {
                let (a, b) = (moment(0), moment(1));
                [a[0] + b[0], a[1] + b[1], a[2] + b[2]]
            }
            Param::Mass => torque(self.com.map(|c| self.g * c)),
            Param::Gravity => torque(self.com.map(|c| self.m * c)),
            Param::Com(k) => {
                let mut d = [0.0; 3];
                d[k] = self.m * self.g;
                torque(d)
            }
            Param::Initial(_) | Param::Viscous | Param::Drag => return [0.0; 3],
        };
        [r[0] * inv[0], r[1] * inv[1], r[2] * inv[2]]
    }
}

/// What the sensitivities ride on: a first-order system whose first seven components are
/// `(q, omega)` of `top()` (a plain heavy top, or a damped one on a fixed pivot with its
/// work and dissipated energy after them), with viscous and drag torques `-(c + k |omega|)
/// omega` at its pivot.
pub trait Carrier<const M: usize>: OdeSystem<M> {
    /// The top.
    fn top(&self) -> &HeavyTop;
    /// The viscous and drag coefficients `(c, k)` of the torque at the pivot.
    fn damping(&self) -> [f64; 2] {
        [0.0; 2]
    }
}

impl<const AXIAL: bool> Carrier<7> for QOmega<'_, AXIAL> {
    fn top(&self) -> &HeavyTop {
        self.0
    }
}

/// The tangent of the damping torque `-(c + k |omega|) omega` along `d_omega`.
#[inline(always)]
fn damping_tangent([c, k]: [f64; 2], omega: [f64; 3], dw: [f64; 3]) -> [f64; 3] {
    let wn = dot(omega, omega).sqrt();
    let along = if wn > 0.0 {
        k * dot(omega, dw) / wn
    } else {
        0.0
    };
    let a = c + k * wn;
    [
        -a * dw[0] - along * omega[0],
        -a * dw[1] - along * omega[1],
        -a * dw[2] - along * omega[2],
    ]
}

/// A carrier of M components with the sensitivities `(xi, d_omega)` of each parameter after
/// it: `N = M + 6 K`, the columns past `params.len()` unused (zero). The carrier's own
/// right-hand side, projection and error scale, so that it runs as a plain run does.
struct WithSensitivities<'a, B, const M: usize> {
    base: &'a B,
    params: &'a [Param],
    control: bool,
}

impl<B: Carrier<M>, const M: usize, const N: usize> OdeSystem<N> for WithSensitivities<'_, B, M> {
    #[inline(always)]
    fn rhs(&self, t: f64, y: &[f64; N], dy: &mut [f64; N]) {
        let top = self.base.top();
        let mut ym = [0.0; M];
        ym.copy_from_slice(&y[..M]);
        let mut dm = [0.0; M];
        self.base.rhs(t, &ym, &mut dm);
        dy[..M].copy_from_slice(&dm);
        let gamma = Quat([y[0], y[1], y[2], y[3]]).up_in_body();
        let omega = [y[4], y[5], y[6]];
        let mom = top.momentum(omega);
        let omega_dot = [dm[4], dm[5], dm[6]];
        let damping = self.base.damping();
        let damped = damping != [0.0; 2];
        let inv = top.inv_inertia;
        for (j, p) in self.params.iter().enumerate() {
            let b = M + 6 * j;
            let mut v = [0.0; 6];
            v.copy_from_slice(&y[b..b + 6]);
            let mut d = top.tangent(gamma, omega, mom, &v);
            let r = top.rate_derivative(p, gamma, omega, omega_dot);
            for i in 0..3 {
                d[3 + i] += r[i];
            }
            if damped {
                let dt = damping_tangent(damping, omega, [v[3], v[4], v[5]]);
                let wn = dot(omega, omega).sqrt();
                // the coefficients' own terms: -omega and -|omega| omega
                let own = match p {
                    Param::Viscous => 1.0,
                    Param::Drag => wn,
                    _ => 0.0,
                };
                for i in 0..3 {
                    d[3 + i] += (dt[i] - own * omega[i]) * inv[i];
                }
            }
            dy[b..b + 6].copy_from_slice(&d);
        }
        for x in dy[M + 6 * self.params.len()..].iter_mut() {
            *x = 0.0;
        }
    }

    fn project(&self, y: &mut [f64; N]) {
        let mut ym = [0.0; M];
        ym.copy_from_slice(&y[..M]);
        self.base.project(&mut ym);
        y[..M].copy_from_slice(&ym);
    }

    #[inline(always)]
    fn magnitude_floor(&self) -> [f64; N] {
        let mut f = [0.0; N];
        f[..M].copy_from_slice(&self.base.magnitude_floor());
        f
    }

    #[inline(always)]
    fn controlled(&self) -> usize {
        if self.control {
            M + 6 * self.params.len()
        } else {
            self.base.controlled()
        }
    }
}

/// A run with sensitivities: times, rows, and per row and parameter `(xi, d_omega)`.
#[derive(Debug, Clone)]
pub struct SensitivitySolution<R> {
    /// Times (s).
    pub t: Vec<f64>,
    /// Rows at those times.
    pub rows: Vec<R>,
    /// `(xi, d_omega)` of every parameter at every time: row-major, `sens[i * k + j]` for
    /// row i and parameter j of k.
    pub sens: Vec<[f64; 6]>,
    /// Counters and status (no events).
    pub info: RunInfo,
}

/// The rules of a run with sensitivities: method "dop853", no events, not the reduced
/// route, 1 to [`MAX_SENSITIVITIES`] names; then the model's own checks.
fn check<T: Model>(model: &T, settings: &Settings, sens: &Sensitivities) -> Result<()> {
    if settings.method != "dop853" {
        return Err(KreiselError::InvalidParameter {
            name: "method".into(),
            value: format!("{:?}", settings.method),
            allowed: "sensitivities are integrated with \"dop853\" only".into(),
        });
    }
    if !settings.events.is_empty() {
        return Err(KreiselError::InvalidParameter {
            name: "events".into(),
            value: format!("{} event(s)", settings.events.len()),
            allowed: "a run with sensitivities takes no events (their times would need \
                      sensitivities of their own)"
                .into(),
        });
    }
    simulate::check(model, settings, 0)?;
    if settings.reduced {
        return Err(KreiselError::InvalidParameter {
            name: "reduced".into(),
            value: "True".into(),
            allowed: "sensitivities are integrated with the whole top, not the reduced route"
                .into(),
        });
    }
    let k = sens.params.len();
    if k == 0 || k > MAX_SENSITIVITIES {
        return Err(KreiselError::invalid(
            "sensitivities",
            k as f64,
            format!("give 1 to {MAX_SENSITIVITIES} names"),
        ));
    }
    Ok(())
}

/// Integrates a carrier of `$m` components with the sensitivities: one monomorphisation
/// per width, exact up to 6 names (a fit's usual count); in the wider ones the unused columns
/// stay zero and are not measured.
macro_rules! run_widths {
    ($m:literal, $base:expr, $y0:expr, $row:expr, $settings:expr, $sens:expr, $go:expr) => {
        match $sens.params.len() {
            1 => run::<_, _, $m, { $m + 6 }>($base, $y0, $row, $settings, $sens, $go),
            2 => run::<_, _, $m, { $m + 12 }>($base, $y0, $row, $settings, $sens, $go),
            3 => run::<_, _, $m, { $m + 18 }>($base, $y0, $row, $settings, $sens, $go),
            4 => run::<_, _, $m, { $m + 24 }>($base, $y0, $row, $settings, $sens, $go),
            5 => run::<_, _, $m, { $m + 30 }>($base, $y0, $row, $settings, $sens, $go),
            6 => run::<_, _, $m, { $m + 36 }>($base, $y0, $row, $settings, $sens, $go),
            7..=9 => run::<_, _, $m, { $m + 54 }>($base, $y0, $row, $settings, $sens, $go),
            _ => run::<_, _, $m, { $m + 6 * MAX_SENSITIVITIES }>(
                $base, $y0, $row, $settings, $sens, $go,
            ),
        }
    };
}

/// Simulates `top` from `s0` with the sensitivities `sens` (method "dop853", no events):
/// the rows are those of [`simulate::simulate`] with the same settings, bit for bit.
pub fn simulate_with_sensitivities(
    top: &HeavyTop,
    s0: &RigidState,
    settings: &Settings,
    sens: &Sensitivities,
    keep_going: &mut dyn FnMut(f64) -> bool,
) -> Result<SensitivitySolution<RigidState>> {
    check(top, settings, sens)?;
    if let Some(i) = sens
        .params
        .iter()
        .position(|p| matches!(p, Param::Viscous | Param::Drag))
    {
        return Err(KreiselError::InvalidParameter {
            name: "sensitivities".into(),
            value: format!("{:?}", sens.names[i]),
            allowed: "an undamped top has no damping coefficients".into(),
        });
    }
    let y0 = pack(s0);
    if top.axial() {
        run_widths!(
            7,
            &QOmega::<true>(top),
            y0,
            &|_t: f64, y: &[f64; 7]| unpack(y),
            settings,
            sens,
            keep_going
        )
    } else {
        run_widths!(
            7,
            &QOmega::<false>(top),
            y0,
            &|_t: f64, y: &[f64; 7]| unpack(y),
            settings,
            sens,
            keep_going
        )
    }
}

/// Simulates a damped top on a fixed pivot (viscous and drag torques, no dry friction) with
/// the sensitivities `sens`, which may name "viscous" and "drag": the rows are those of
/// [`simulate::simulate`] with the same settings, bit for bit.
pub fn simulate_damped_with_sensitivities(
    top: &DrivenTop,
    s0: &RigidState,
    settings: &Settings,
    sens: &Sensitivities,
    keep_going: &mut dyn FnMut(f64) -> bool,
) -> Result<SensitivitySolution<DrivenRow>> {
    if !matches!(top.pivot(), Pivot::Fixed) || top.damping().dry * top.damping().pivot_radius > 0.0
    {
        return Err(unavailable(false));
    }
    check(top, settings, sens)?;
    let (sys, y0) = top.smooth_system(s0);
    let row = |t: f64, y: &[f64; DIM]| DrivenRow {
        t,
        y: *y,
        stuck: false,
    };
    run_widths!(9, &sys, y0, &row, settings, sens, keep_going)
}

fn run<B: Carrier<M>, R, const M: usize, const N: usize>(
    base: &B,
    y0m: [f64; M],
    row: &dyn Fn(f64, &[f64; M]) -> R,
    settings: &Settings,
    sens: &Sensitivities,
    keep_going: &mut dyn FnMut(f64) -> bool,
) -> Result<SensitivitySolution<R>> {
    let k = sens.params.len();
    debug_assert!(M + 6 * k <= N);
    let mut y0 = [0.0; N];
    y0[..M].copy_from_slice(&y0m);
    for (j, p) in sens.params.iter().enumerate() {
        if let Param::Initial(v) = p {
            y0[M + 6 * j..M + 6 + 6 * j].copy_from_slice(v);
        }
    }
    let integrator = settings.dop853();
    let (mut t, mut rows, mut out) = (Vec::new(), Vec::new(), Vec::new());
    let full = std::cell::Cell::new(false);
    let t_end = settings.t_end;
    let mut go = |ti: f64| !full.get() && keep_going(ti);
    let mut stream = Stream::new(
        settings.t_eval.as_deref(),
        false,
        Some(&mut go),
        |ti, y: &[f64; N]| {
            if t.len() >= MAX_ROWS {
                full.set(true);
                return;
            }
            t.push(ti);
            let mut ym = [0.0; M];
            ym.copy_from_slice(&y[..M]);
            rows.push(row(ti, &ym));
            for j in 0..k {
                let mut v = [0.0; 6];
                v.copy_from_slice(&y[M + 6 * j..M + 6 + 6 * j]);
                out.push(v);
            }
        },
    );
    let sys = WithSensitivities::<B, M> {
        base,
        params: &sens.params,
        control: sens.control,
    };
    let result = integrator.integrate(&sys, 0.0, y0, t_end, &mut stream);
    let (t1, _, st) = result.map_err(|e| integrate_error(e, t_end))?;
    if full.get() {
        return Err(KreiselError::invalid(
            "t_end",
            t_end,
            format!(
                "the run keeps a row per step and reached the {MAX_ROWS} rows: give t_eval \
                 or a shorter t_end"
            ),
        ));
    }
    let mut stats = Stats::default();
    stats += st;
    Ok(SensitivitySolution {
        t,
        rows,
        sens: out,
        info: RunInfo {
            stats,
            events: Vec::new(),
            status: if t1 < t_end {
                Status::Interrupted
            } else {
                Status::Completed
            },
        },
    })
}

#[cfg(test)]
// component loops compare vectors index by index; the cases pair a parameter with its top
#[allow(clippy::needless_range_loop, clippy::type_complexity)]
mod tests {
    use super::*;
    use crate::rotation::quaternion_from_euler;

    fn general() -> HeavyTop {
        HeavyTop::new(1.1, 1.6, 0.9, 0.7, [0.12, -0.08, 0.35], 9.81).unwrap()
    }

    fn state() -> RigidState {
        RigidState::new(quaternion_from_euler(0.3, 0.8, -0.4).0, [1.3, -0.7, 11.0]).unwrap()
    }

    /// The rates' right-hand side at `(q, omega)` of `top`.
    fn rates(top: &HeavyTop, q: Quat, omega: [f64; 3]) -> [f64; 7] {
        let y = [q.0[0], q.0[1], q.0[2], q.0[3], omega[0], omega[1], omega[2]];
        let mut d = [0.0; 7];
        top.rhs(&y, &mut d);
        d
    }

    fn rel(a: f64, b: f64) -> f64 {
        (a - b).abs() / b.abs().max(1.0)
    }

    #[test]
    fn sensitivity_tangent_is_the_derivative_of_the_right_hand_side() {
        // df/dy along (xi, d_omega), against central differences of the right-hand side at
        // (q exp(h xi / 2), omega + h d_omega): the rates' part directly; the orientation's
        // from d/dh of q' = d/dt(q exp(h xi/2)) = q' (0, xi)/2 + q (0, xi')/2 at h = 0.
        let top = general();
        let s = state();
        let v = [0.3, -0.5, 0.2, 0.7, 0.4, -1.1];
        let h = 1e-6;
        let at = |h: f64| {
            let q =
                s.q.hamilton(Quat::from_rotation_vector([h * v[0], h * v[1], h * v[2]]));
            let w = [
                s.omega[0] + h * v[3],
                s.omega[1] + h * v[4],
                s.omega[2] + h * v[5],
            ];
            rates(&top, q, w)
        };
        let (p, m) = (at(h), at(-h));
        let fd: Vec<f64> = (0..7).map(|i| (p[i] - m[i]) / (2.0 * h)).collect();
        let (gamma, mom) = (s.q.up_in_body(), top.momentum(s.omega));
        let d = top.tangent(gamma, s.omega, mom, &v);
        for i in 0..3 {
            assert!(
                rel(d[3 + i], fd[4 + i]) < 1e-8,
                "{i}: {} {}",
                d[3 + i],
                fd[4 + i]
            );
        }
        let f0 = rates(&top, s.q, s.omega);
        let qdot = Quat([f0[0], f0[1], f0[2], f0[3]]);
        let rot = qdot.hamilton(Quat([0.0, v[0], v[1], v[2]]));
        // q (0, xi') / 2 = fd - q' (0, xi) / 2, so (0, xi') = 2 q* (fd - q'(0, xi)/2).
        let rest = Quat([
            fd[0] - 0.5 * rot.0[0],
            fd[1] - 0.5 * rot.0[1],
            fd[2] - 0.5 * rot.0[2],
            fd[3] - 0.5 * rot.0[3],
        ]);
        let conj = Quat([s.q.0[0], -s.q.0[1], -s.q.0[2], -s.q.0[3]]);
        let dxi = conj.hamilton(rest);
        assert!(dxi.0[0].abs() < 1e-8, "{:?}", dxi);
        for i in 0..3 {
            assert!(
                rel(d[i], 2.0 * dxi.0[1 + i]) < 1e-8,
                "{i}: {} {}",
                d[i],
                dxi.0[1 + i]
            );
        }
    }

    #[test]
    fn sensitivity_parameter_terms_are_the_derivatives_of_the_right_hand_side() {
        // df/dp against central differences of the right-hand side of perturbed tops.
        let s = state();
        let (i, m, c, g) = ([1.1, 1.6, 0.9], 0.7, [0.12, -0.08, 0.35], 9.81);
        let make = |i: [f64; 3], m: f64, c: [f64; 3], g: f64| {
            HeavyTop::new(i[0], i[1], i[2], m, c, g).unwrap()
        };
        let top = make(i, m, c, g);
        let f0 = rates(&top, s.q, s.omega);
        let wdot = [f0[4], f0[5], f0[6]];
        let h = 1e-6;
        let cases: Vec<(Param, Box<dyn Fn(f64) -> HeavyTop>)> = vec![
            (
                Param::Inertia(0),
                Box::new(|d| make([i[0] + d, i[1], i[2]], m, c, g)),
            ),
            (
                Param::Inertia(1),
                Box::new(|d| make([i[0], i[1] + d, i[2]], m, c, g)),
            ),
            (
                Param::Inertia(2),
                Box::new(|d| make([i[0], i[1], i[2] + d], m, c, g)),
            ),
            (
                Param::Transverse,
                Box::new(|d| make([i[0] + d, i[1] + d, i[2]], m, c, g)),
            ),
            (Param::Mass, Box::new(|d| make(i, m + d, c, g))),
            (Param::Gravity, Box::new(|d| make(i, m, c, g + d))),
            (
                Param::Com(0),
                Box::new(|d| make(i, m, [c[0] + d, c[1], c[2]], g)),
            ),
            (
                Param::Com(1),
                Box::new(|d| make(i, m, [c[0], c[1] + d, c[2]], g)),
            ),
            (
                Param::Com(2),
                Box::new(|d| make(i, m, [c[0], c[1], c[2] + d], g)),
            ),
        ];
        for (p, perturbed) in cases {
            let (a, b) = (
                rates(&perturbed(h), s.q, s.omega),
                rates(&perturbed(-h), s.q, s.omega),
            );
            let r = top.rate_derivative(&p, s.q.up_in_body(), s.omega, wdot);
            for k in 0..3 {
                let fd = (a[4 + k] - b[4 + k]) / (2.0 * h);
                assert!(rel(r[k], fd) < 1e-7, "{p:?} {k}: {} {fd}", r[k]);
            }
        }
    }

    #[test]
    fn sensitivity_of_the_euler_state_moves_the_rigid_state() {
        // dy0/dp of an Euler-angle state against differences of its conversion.
        let e = [0.8, 0.3, -0.4, 0.6, 1.7, 11.0];
        let rigid = |e: [f64; 6]| {
            let q = quaternion_from_euler(e[1], e[0], e[2]);
            let w = crate::rotation::omega_body_from_euler(e[0], e[2], e[3], e[4], e[5]);
            (q, w)
        };
        let (q0, _) = rigid(e);
        let conj = Quat([q0.0[0], -q0.0[1], -q0.0[2], -q0.0[3]]);
        let h = 1e-6;
        for j in 0..6 {
            let (mut a, mut b) = (e, e);
            a[j] += h;
            b[j] -= h;
            let ((qa, wa), (qb, wb)) = (rigid(a), rigid(b));
            let v = euler_initial(e, j);
            // xi from the quaternion's change: dq = q (0, xi) / 2.
            let dq = Quat(std::array::from_fn(|i| (qa.0[i] - qb.0[i]) / (2.0 * h)));
            let xi = conj.hamilton(dq);
            for i in 0..3 {
                assert!((v[i] - 2.0 * xi.0[1 + i]).abs() < 1e-8, "{j} xi {i}");
                let fd = (wa[i] - wb[i]) / (2.0 * h);
                assert!(rel(v[3 + i], fd) < 1e-8, "{j} omega {i}: {} {fd}", v[3 + i]);
            }
            // and back: the Euler angles' derivative along xi is the unit vector of j
            if j < 3 {
                let d = euler_derivative(q0, [v[0], v[1], v[2]]);
                let unit = [[1.0, 0.0, 0.0], [0.0, 1.0, 0.0], [0.0, 0.0, 1.0]][j];
                for i in 0..3 {
                    assert!((d[i] - unit[i]).abs() < 1e-12, "{j} euler {i}: {d:?}");
                }
            }
        }
    }

    #[test]
    fn sensitivities_leave_the_trajectory_bit_for_bit() {
        let top = general();
        let st = Settings {
            t_end: 2.0,
            ..Settings::default()
        };
        let plain = simulate::simulate(&top, &state(), &st, &mut [], &mut |_| true).unwrap();
        let names: Vec<String> = ["I1", "com[1]", "omega[2]"].map(String::from).to_vec();
        let sens = Sensitivities::new(&names, false, false, None).unwrap();
        let out = simulate_with_sensitivities(&top, &state(), &st, &sens, &mut |_| true).unwrap();
        assert_eq!(out.t, plain.t);
        assert_eq!(out.rows, plain.rows);
        assert_eq!(out.info.stats, plain.info.stats);
        assert_eq!(out.sens.len(), 3 * out.t.len());
    }

    #[test]
    fn sensitivity_of_a_damped_top_is_the_derivative_of_its_right_hand_side() {
        // The damping torque's tangent and the coefficients' own terms, against central
        // differences of the damped top's right-hand side (body rates moved, coefficients
        // moved).
        use super::super::driven::Damping;
        let make = |c: f64, k: f64| {
            let d = Damping::new(c, k, 0.0, 0.0).unwrap();
            DrivenTop::new(general(), Pivot::Fixed, d).unwrap()
        };
        let (c, k) = (0.05, 0.02);
        let top = make(c, k);
        let s = state();
        let dw = [0.7, 0.4, -1.1];
        let params = [
            Param::Initial([0.0, 0.0, 0.0, dw[0], dw[1], dw[2]]),
            Param::Viscous,
            Param::Drag,
        ];
        let (sys, y0) = top.smooth_system(&s);
        let ext = WithSensitivities::<_, DIM> {
            base: &sys,
            params: &params,
            control: false,
        };
        let mut y = [0.0; DIM + 18];
        y[..DIM].copy_from_slice(&y0);
        y[DIM + 3..DIM + 6].copy_from_slice(&dw);
        let mut dy = [0.0; DIM + 18];
        ext.rhs(0.0, &y, &mut dy);
        let rates = |top: &DrivenTop, h: f64| {
            let mut s = s;
            for i in 0..3 {
                s.omega[i] += h * dw[i];
            }
            let (sys, y) = top.smooth_system(&s);
            let mut d = [0.0; DIM];
            sys.rhs(0.0, &y, &mut d);
            [d[4], d[5], d[6]]
        };
        let h = 1e-6;
        let cases: [(usize, [f64; 3], [f64; 3]); 3] = [
            (0, rates(&top, h), rates(&top, -h)),
            (1, rates(&make(c + h, k), 0.0), rates(&make(c - h, k), 0.0)),
            (2, rates(&make(c, k + h), 0.0), rates(&make(c, k - h), 0.0)),
        ];
        for (j, a, b) in cases {
            for i in 0..3 {
                let fd = (a[i] - b[i]) / (2.0 * h);
                let got = dy[DIM + 6 * j + 3 + i];
                assert!(rel(got, fd) < 1e-7, "{j} {i}: {got} {fd}");
            }
        }
    }

    #[test]
    fn damped_sensitivities_leave_the_trajectory_bit_for_bit() {
        use super::super::driven::Damping;
        let d = Damping::new(0.05, 0.02, 0.0, 0.0).unwrap();
        let top = DrivenTop::new(general(), Pivot::Fixed, d).unwrap();
        let st = Settings {
            t_end: 2.0,
            ..Settings::default()
        };
        let plain = simulate::simulate(&top, &state(), &st, &mut [], &mut |_| true).unwrap();
        let names: Vec<String> = ["viscous", "drag", "I3"].map(String::from).to_vec();
        let sens = Sensitivities::new(&names, false, true, None).unwrap();
        let out =
            simulate_damped_with_sensitivities(&top, &state(), &st, &sens, &mut |_| true).unwrap();
        assert_eq!(out.t, plain.t);
        assert_eq!(out.rows, plain.rows);
        assert_eq!(out.info.stats, plain.info.stats);
        // and the undamped top refuses the coefficients
        let e = Sensitivities::new(&names, false, false, None).unwrap_err();
        assert!(e.to_string().contains("\"viscous\""), "{e}");
    }

    #[test]
    fn sensitivity_names_are_checked() {
        let n = |v: &[&str]| v.iter().map(|s| s.to_string()).collect::<Vec<_>>();
        let e = Sensitivities::new(&n(&["I2"]), true, false, None).unwrap_err();
        assert!(e.to_string().contains("\"I2\""), "{e}");
        assert!(e.to_string().contains("I1, I3, m, l, g"), "{e}");
        let e = Sensitivities::new(&n(&["m", "m"]), false, false, None).unwrap_err();
        assert!(e.to_string().contains("at most once"), "{e}");
        let e = Sensitivities::new(&n(&["theta"]), false, false, None).unwrap_err();
        assert!(e.to_string().contains("orientation[0]"), "{e}");
        assert!(Sensitivities::new(&n(&["theta"]), false, false, Some([0.5; 6])).is_ok());
    }
}
