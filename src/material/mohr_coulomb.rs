//! Non-associated Mohr–Coulomb plasticity: the yield criterion of soil mechanics classes, with
//! the same parameters as the Drucker–Prager sand (friction angle φ, dilatancy angle ψ,
//! cohesion c, and E, ν, density).
//!
//! With the principal stresses ordered σ1 ≥ σ2 ≥ σ3 (tension positive), the yield function
//! and the plastic potential are
//!
//! f = (σ1 − σ3) + (σ1 + σ3) sin φ − 2c cos φ,   g = (σ1 − σ3) + (σ1 + σ3) sin ψ:
//!
//! on the plane of the largest and smallest principal stress, the Mohr circle's radius
//! (σ1 − σ3)/2 reaches c cos φ + σ_m sin φ with σ_m = −(σ1 + σ3)/2 (compression positive),
//! i.e. the shear stress on the most loaded plane reaches τ = c + σ_n tan φ. In principal
//! stress space the surface is a hexagonal pyramid about the hydrostatic axis with its apex at
//! σ1 = σ2 = σ3 = c cot φ.
//!
//! The stress update is the others' hypoelastic Jaumann-rate elastic predictor
//! ([`Elastic::trial`]) followed by the return mapping of de Souza Neto, Perić and Owen
//! (2008, *Computational Methods for Plasticity*, Sec. 8.2) in principal stress space, exact
//! in one step for perfect plasticity (f and g are linear in the principal stresses):
//!
//! - **face**: σ ← σ_tr − Δλ D m_A with m_A = ∂g/∂σ = (1 + sin ψ, 0, −(1 − sin ψ)) and
//!   Δλ = f(σ_tr) / (n_A · D m_A), n_A = ∂f/∂σ = (1 + sin φ, 0, −(1 − sin φ)),
//!   (D m)_k = 2G m_k + (K − 2G/3) Σ_j m_j; kept if the returned stresses keep their order;
//! - **edge**: else onto the edge σ1 = σ2 (triaxial compression; if the face return put σ1
//!   below σ2) or σ2 = σ3 (triaxial extension), two multipliers from the two planes' linear
//!   equations, kept if both are positive and the stress is not past the apex;
//! - **apex**: else σ1 = σ2 = σ3 = c cot φ (cohesionless: a stress-free particle).
//!
//! The returned principal stresses are put back along the trial's principal directions (the
//! return of an isotropic model is coaxial). In plane strain the out-of-plane stress σ_zz is
//! one of the three principal stresses and takes part in the return like the others.
//!
//! **Lanes.** Unlike the other models, the return branches per particle (the order of the
//! principal stresses, face, edge or apex) and needs the principal directions: each particle
//! in a group of lanes is returned on its own, with the same scalar arithmetic, so the lanes
//! give exactly the scalar results. Past the apex nothing resists an expansion: its grains part
//! and close again as the Drucker–Prager sand's do ([`Constitutive::packed_specific_volume`]).

use super::{Constitutive, Elastic, ElasticParams, PqSurface, StressUpdate};
use crate::error::{Error, Result, check_non_negative, check_range};
use crate::math::{Batch, LANES, Real, Real4, Real4x2, Sym2, Sym3, SymTensor};
use serde::{Deserialize, Serialize};
use std::any::Any;

/// Parameters: E (Pa), ν, density (kg/m³), friction angle φ ∈ [0°, 90°), dilatancy angle
/// ψ ∈ [0°, φ] and cohesion c ≥ 0 (Pa): the Drucker–Prager sand's.
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct MohrCoulombParams {
    pub youngs_modulus: f64,
    pub poisson_ratio: f64,
    pub density: f64,
    pub friction_angle: f64,
    #[serde(default)]
    pub dilatancy_angle: f64,
    #[serde(default)]
    pub cohesion: f64,
}

impl MohrCoulombParams {
    pub fn elastic(&self) -> ElasticParams {
        ElasticParams {
            youngs_modulus: self.youngs_modulus,
            poisson_ratio: self.poisson_ratio,
            density: self.density,
        }
    }

    pub fn validate(&self, path: &str) -> Result<()> {
        self.elastic().validate(path)?;
        check_range(
            format!("{path}.friction_angle"),
            self.friction_angle,
            0.0,
            90.0,
            true,
            "degrees",
        )?;
        let psi = self.dilatancy_angle;
        if !(psi.is_finite() && psi >= 0.0 && psi <= self.friction_angle) {
            return Err(Error::invalid(
                format!("{path}.dilatancy_angle"),
                psi,
                format!(
                    "must be in [0, {}] (degrees; at most the friction angle)",
                    self.friction_angle
                ),
            ));
        }
        check_non_negative(format!("{path}.cohesion"), self.cohesion, "Pa")
    }

    /// The pyramid's meridians in p–q space (p = −tr σ/3, q = √(3 J2)). On a triaxial
    /// meridian q = |σ_axial − σ_lateral|; the surface is drawn on the **triaxial compression**
    /// meridian (Lode angle θ = −30°: σ1 = σ2 > σ3, the axial stress the most compressive),
    /// q = 6 (p sin φ + c cos φ)/(3 − sin φ), the outer one; the **triaxial extension**
    /// meridian (θ = +30°: σ1 > σ2 = σ3), q = 6 (p sin φ + c cos φ)/(3 + sin φ), is the inner
    /// one (`lower_*`). Every other stress at yield lies between the two; both end at the apex
    /// p = −c cot φ.
    pub fn pq_surface(&self) -> PqSurface {
        let (s, c) = self.friction_angle.to_radians().sin_cos();
        let coh = 6.0 * self.cohesion * c;
        PqSurface {
            kind: "mohr_coulomb",
            label: "Mohr–Coulomb: triaxial compression and extension",
            slope: 6.0 * s / (3.0 - s),
            intercept: coh / (3.0 - s),
            apex_p: if s > 0.0 {
                -self.cohesion * c / s
            } else {
                f64::NEG_INFINITY
            },
            lower: Some((6.0 * s / (3.0 + s), coh / (3.0 + s))),
        }
    }

    pub fn model(&self) -> MohrCoulomb {
        let (sin_phi, cos_phi) = self.friction_angle.to_radians().sin_cos();
        let elastic = self.elastic();
        MohrCoulomb {
            elastic: elastic.model(),
            g: elastic.shear_modulus(),
            k: elastic.bulk_modulus(),
            sin_phi,
            sin_psi: self.dilatancy_angle.to_radians().sin(),
            two_c_cos_phi: 2.0 * self.cohesion * cos_phi,
            apex: if sin_phi > 0.0 {
                self.cohesion * cos_phi / sin_phi
            } else {
                f64::INFINITY
            },
            packed_specific_volume: (1.0 / self.density) as Real,
        }
    }
}

/// The Mohr–Coulomb model with its constants (in f64: the return is computed in double
/// precision whatever [`Real`] is).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct MohrCoulomb {
    pub elastic: Elastic,
    /// G and K (Pa).
    pub g: f64,
    pub k: f64,
    pub sin_phi: f64,
    pub sin_psi: f64,
    /// 2c cos φ.
    pub two_c_cos_phi: f64,
    /// The apex's principal stress c cot φ (Pa; infinite for φ = 0).
    pub apex: f64,
    /// 1/ρ (m³/kg): the packed volume per unit mass.
    pub packed_specific_volume: Real,
}

/// The planes of the pyramid near the largest and smallest principal stress, as the indices
/// (i, j) of their σ_i − σ_j: A = (0, 2), the face of the ordered stresses; B = (1, 2) and
/// C = (0, 1), the neighbouring faces that meet A on the edges σ1 = σ2 and σ2 = σ3.
const A: (usize, usize) = (0, 2);
const B: (usize, usize) = (1, 2);
const C: (usize, usize) = (0, 1);

impl MohrCoulomb {
    /// f on the plane (i, j): (σ_i − σ_j) + (σ_i + σ_j) sin φ − 2c cos φ.
    fn plane(&self, s: [f64; 3], (i, j): (usize, usize)) -> f64 {
        (s[i] - s[j]) + (s[i] + s[j]) * self.sin_phi - self.two_c_cos_phi
    }

    /// The largest f over the six planes (every ordering of the principal stresses): the
    /// yield function of unordered principal stresses.
    pub fn yield_function(&self, s: [f64; 3]) -> f64 {
        let mut f = f64::NEG_INFINITY;
        for i in 0..3 {
            for j in 0..3 {
                if i != j {
                    f = f.max(self.plane(s, (i, j)));
                }
            }
        }
        f
    }

    /// The gradient of a plane (i, j) with the angle whose sine is `sin`: 1 + sin at i,
    /// −(1 − sin) at j.
    fn gradient((i, j): (usize, usize), sin: f64) -> [f64; 3] {
        let mut n = [0.0; 3];
        n[i] = 1.0 + sin;
        n[j] = -(1.0 - sin);
        n
    }

    /// D m: the stress change per unit multiplier of a plastic flow along m.
    fn elastic_of(&self, m: [f64; 3]) -> [f64; 3] {
        let lame = (self.k - 2.0 * self.g / 3.0) * (m[0] + m[1] + m[2]);
        m.map(|x| 2.0 * self.g * x + lame)
    }

    /// The return of ordered principal stresses `s` (σ1 ≥ σ2 ≥ σ3) that violate the face A.
    pub fn return_principal(&self, s: [f64; 3]) -> [f64; 3] {
        let dot = |a: [f64; 3], b: [f64; 3]| a[0] * b[0] + a[1] * b[1] + a[2] * b[2];
        let flow = |plane| self.elastic_of(Self::gradient(plane, self.sin_psi));
        let normal = |plane| Self::gradient(plane, self.sin_phi);
        let (da, na) = (flow(A), normal(A));
        let fa = self.plane(s, A);
        // face
        let dl = fa / dot(na, da);
        let face: [f64; 3] = std::array::from_fn(|k| s[k] - dl * da[k]);
        let scale = s.iter().fold(self.two_c_cos_phi, |m, x| m.max(x.abs()));
        let tol = 1e-12 * scale;
        if face[0] >= face[1] - tol && face[1] >= face[2] - tol {
            return face;
        }
        // edge: σ1 = σ2 if the face return put σ1 below σ2, else σ2 = σ3 (the other one
        // if that fails)
        let edges = if face[0] < face[1] { [B, C] } else { [C, B] };
        for other in edges {
            let (dx, nx) = (flow(other), normal(other));
            let fx = self.plane(s, other);
            let (a11, a12, a21, a22) = (dot(na, da), dot(na, dx), dot(nx, da), dot(nx, dx));
            let det = a11 * a22 - a12 * a21;
            let la = (fa * a22 - a12 * fx) / det;
            let lx = (a11 * fx - a21 * fa) / det;
            let edge: [f64; 3] = std::array::from_fn(|k| s[k] - la * da[k] - lx * dx[k]);
            let mean = (edge[0] + edge[1] + edge[2]) / 3.0;
            if la >= 0.0 && lx >= 0.0 && mean <= self.apex {
                return edge;
            }
        }
        // apex
        [self.apex; 3]
    }

    /// The return of one particle's trial stress (3D components; a plane-strain stress has
    /// xz = yz = 0): the stress and what the update did.
    pub fn return_stress(&self, trial: Sym3) -> (Sym3, StressUpdate) {
        let e = &self.elastic;
        let energy_trial = e.energy_density(trial);
        let m = [
            [trial.xx as f64, trial.xy as f64, trial.xz as f64],
            [trial.xy as f64, trial.yy as f64, trial.yz as f64],
            [trial.xz as f64, trial.yz as f64, trial.zz as f64],
        ];
        let (values, vectors) = eigen_symmetric(m);
        let mut order = [0, 1, 2];
        order.sort_by(|&a, &b| values[b].total_cmp(&values[a]));
        let s = order.map(|k| values[k]);
        let f = self.plane(s, A);
        if f.is_nan() || f <= 0.0 {
            // inside the pyramid (or not a number, which the solver reports)
            return (trial, StressUpdate::elastic(energy_trial));
        }
        let r = self.return_principal(s);
        // σ = σ_tr + Σ_k (σ'_k − σ_k) n_k n_kᵀ
        let d = std::array::from_fn::<f64, 3, _>(|k| r[k] - s[k]);
        let mut out = m;
        for (k, &o) in order.iter().enumerate() {
            let n = [vectors[0][o], vectors[1][o], vectors[2][o]];
            for a in 0..3 {
                for b in 0..3 {
                    out[a][b] += d[k] * n[a] * n[b];
                }
            }
        }
        let stress = Sym3 {
            xx: out[0][0] as Real,
            yy: out[1][1] as Real,
            zz: out[2][2] as Real,
            xy: out[0][1] as Real,
            xz: if trial.xz == 0.0 && trial.yz == 0.0 {
                0.0
            } else {
                out[0][2] as Real
            },
            yz: if trial.xz == 0.0 && trial.yz == 0.0 {
                0.0
            } else {
                out[1][2] as Real
            },
        };
        // the plastic strain increment is C⁻¹ (σ_tr − σ); its deviator is dev(σ_tr − σ)/(2G)
        let mean = (d[0] + d[1] + d[2]) / 3.0;
        let dev2: f64 = d.iter().map(|x| (x - mean) * (x - mean)).sum();
        let energy = e.energy_density(stress);
        // the plastic work σ:Δε_p = −σ':C⁻¹:d in the principal frame (the returned stress σ'
        // shares the trial's directions)
        let r_mean = (r[0] + r[1] + r[2]) / 3.0;
        let work = -(0..3).map(|k| (r[k] - r_mean) * (d[k] - mean)).sum::<f64>() / (2.0 * self.g)
            - r_mean * mean / self.k;
        let update = StressUpdate {
            plastic_strain: ((2.0 / 3.0 * dev2).sqrt() / (2.0 * self.g)) as Real,
            dissipation: work as Real,
            energy,
        };
        (stress, update)
    }
}

/// The eigenvalues and eigenvectors (the columns of the second matrix) of a symmetric 3×3
/// matrix, by cyclic Jacobi rotations. A matrix with no xz and yz coupling (plane strain) is
/// only rotated in the xy plane, so that z stays a principal direction exactly: one rotation
/// by the angle that zeroes xy, taken in closed form (a_xx − t a_xy, a_yy + t a_xy).
pub fn eigen_symmetric(a: [[f64; 3]; 3]) -> ([f64; 3], [[f64; 3]; 3]) {
    if a[0][2] == 0.0 && a[1][2] == 0.0 {
        return eigen_plane(a);
    }
    eigen_jacobi(a)
}

/// The cyclic Jacobi sweeps behind [`eigen_symmetric`], for any symmetric matrix.
fn eigen_jacobi(mut a: [[f64; 3]; 3]) -> ([f64; 3], [[f64; 3]; 3]) {
    let mut v = [[1.0, 0.0, 0.0], [0.0, 1.0, 0.0], [0.0, 0.0, 1.0]];
    for _sweep in 0..50 {
        let off = a[0][1].abs() + a[0][2].abs() + a[1][2].abs();
        let diag = a[0][0].abs() + a[1][1].abs() + a[2][2].abs();
        if off <= 1e-15 * diag || off == 0.0 || !off.is_finite() {
            break;
        }
        for (p, q) in [(0, 1), (0, 2), (1, 2)] {
            if a[p][q] == 0.0 {
                continue;
            }
            // the rotation that zeroes a_pq: t = tan θ, the smaller root of t² + 2τt − 1 = 0
            let tau = (a[q][q] - a[p][p]) / (2.0 * a[p][q]);
            let t = tau.signum() / (tau.abs() + (1.0 + tau * tau).sqrt());
            let c = 1.0 / (1.0 + t * t).sqrt();
            let s = t * c;
            for k in 0..3 {
                let (akp, akq) = (a[k][p], a[k][q]);
                a[k][p] = c * akp - s * akq;
                a[k][q] = s * akp + c * akq;
            }
            for k in 0..3 {
                let (apk, aqk) = (a[p][k], a[q][k]);
                a[p][k] = c * apk - s * aqk;
                a[q][k] = s * apk + c * aqk;
            }
            for row in v.iter_mut() {
                let (vp, vq) = (row[p], row[q]);
                row[p] = c * vp - s * vq;
                row[q] = s * vp + c * vq;
            }
        }
    }
    ([a[0][0], a[1][1], a[2][2]], v)
}

/// [`eigen_symmetric`] of a matrix with no xz and yz coupling, a specialisation of
/// [`eigen_jacobi`] tested against it: the one Jacobi rotation in the xy plane, with t = tan θ
/// the smaller root of t² + 2τt − 1 = 0, τ = (a_yy − a_xx)/(2 a_xy).
fn eigen_plane(a: [[f64; 3]; 3]) -> ([f64; 3], [[f64; 3]; 3]) {
    let axy = a[0][1];
    if axy == 0.0 || !axy.is_finite() {
        let v = [[1.0, 0.0, 0.0], [0.0, 1.0, 0.0], [0.0, 0.0, 1.0]];
        return ([a[0][0], a[1][1], a[2][2]], v);
    }
    let tau = (a[1][1] - a[0][0]) / (2.0 * axy);
    let t = tau.signum() / (tau.abs() + (1.0 + tau * tau).sqrt());
    let c = 1.0 / (1.0 + t * t).sqrt();
    let s = t * c;
    let v = [[c, s, 0.0], [-s, c, 0.0], [0.0, 0.0, 1.0]];
    ([a[0][0] - t * axy, a[1][1] + t * axy, a[2][2]], v)
}

/// Takes `value` as a `B` if `A` is `B` (a generic tensor as one of the concrete ones).
fn cast<A: 'static, B: 'static>(value: A) -> Option<B> {
    let mut slot = Some(value);
    (&mut slot as &mut dyn Any)
        .downcast_mut::<Option<B>>()
        .and_then(Option::take)
}

fn plane(s: Sym2) -> Sym3 {
    Sym3 {
        xx: s.xx,
        yy: s.yy,
        zz: s.zz,
        xy: s.xy,
        xz: 0.0,
        yz: 0.0,
    }
}

fn in_plane(s: Sym3) -> Sym2 {
    Sym2 {
        xx: s.xx,
        yy: s.yy,
        zz: s.zz,
        xy: s.xy,
    }
}

/// `f` on each particle's trial stress held in `trial`: one (2D or 3D), or one per lane.
fn each_particle<S: SymTensor>(
    trial: S,
    f: &impl Fn(Sym3) -> (Sym3, StressUpdate),
) -> (S, StressUpdate<S::Scalar>) {
    fn lanes(u: [StressUpdate; LANES]) -> StressUpdate<Real4> {
        StressUpdate {
            plastic_strain: Real4::from_array(u.map(|u| u.plastic_strain)),
            dissipation: Real4::from_array(u.map(|u| u.dissipation)),
            energy: Real4::from_array(u.map(|u| u.energy)),
        }
    }
    fn pair(a: StressUpdate<Real4>, b: StressUpdate<Real4>) -> StressUpdate<Real4x2> {
        StressUpdate {
            plastic_strain: Real4x2(a.plastic_strain, b.plastic_strain),
            dissipation: Real4x2(a.dissipation, b.dissipation),
            energy: Real4x2(a.energy, b.energy),
        }
    }
    /// The results as the caller's types (which they are).
    fn back<S: SymTensor, T: 'static, U: 'static>(s: T, u: U) -> (S, StressUpdate<S::Scalar>) {
        (cast(s).expect("same type"), cast(u).expect("same type"))
    }
    if let Some(t) = cast::<S, Sym3>(trial) {
        let (s, u) = f(t);
        return back(s, u);
    }
    if let Some(t) = cast::<S, Sym2>(trial) {
        let (s, u) = f(plane(t));
        return back(in_plane(s), u);
    }
    if let Some(t) = cast::<S, Sym3<Real4>>(trial) {
        let out = Sym3::unpack(t).map(f);
        return back(Sym3::pack(&out.map(|o| o.0)), lanes(out.map(|o| o.1)));
    }
    if let Some(t) = cast::<S, Sym2<Real4>>(trial) {
        let out = Sym2::unpack(t).map(|t| f(plane(t)));
        return back(
            Sym2::pack(&out.map(|o| in_plane(o.0))),
            lanes(out.map(|o| o.1)),
        );
    }
    if let Some(t) = cast::<S, Sym3<Real4x2>>(trial) {
        let (a, b) = Sym3::unzip(t);
        let ((a, ua), (b, ub)) = (each_particle(a, f), each_particle(b, f));
        return back(Sym3::zip(a, b), pair(ua, ub));
    }
    if let Some(t) = cast::<S, Sym2<Real4x2>>(trial) {
        let (a, b) = Sym2::unzip(t);
        let ((a, ua), (b, ub)) = (each_particle(a, f), each_particle(b, f));
        return back(Sym2::zip(a, b), pair(ua, ub));
    }
    unreachable!("a stress tensor of a type the solver does not use")
}

impl Constitutive for MohrCoulomb {
    const PLASTIC: bool = true;
    fn update<S: SymTensor>(
        &self,
        stress: &mut S,
        rate: S,
        spin: S::Spin,
        _plastic_strain: S::Scalar,
        dt: Real,
    ) -> StressUpdate<S::Scalar> {
        let trial = self.elastic.trial(*stress, rate, spin, dt);
        let (s, u) = each_particle(trial, &|t| self.return_stress(t));
        *stress = s;
        u
    }
    fn elastic(&self) -> &Elastic {
        &self.elastic
    }
    fn packed_specific_volume(&self) -> Option<Real> {
        Some(self.packed_specific_volume)
    }
}

impl super::Kind for MohrCoulombParams {
    const NAME: &'static str = "mohr_coulomb";
    const LABEL: &'static str = "Mohr–Coulomb";
    const HINT: &'static str = "granular: Mohr–Coulomb";
    const FIELDS: &'static [&'static str] = &[
        "friction_angle",
        "dilatancy_angle",
        "cohesion",
        "youngs_modulus",
        "poisson_ratio",
        "density",
    ];
    type Model = MohrCoulomb;
    /// The Drucker–Prager sand's preset.
    fn preset() -> Self {
        MohrCoulombParams {
            youngs_modulus: 3.5e5,
            poisson_ratio: 0.3,
            density: 2200.0,
            friction_angle: 35.0,
            dilatancy_angle: 0.0,
            cohesion: 0.0,
        }
    }
    fn elastic_params(&self) -> ElasticParams {
        self.elastic()
    }
    fn check(&self, path: &str) -> Result<()> {
        self.validate(path)
    }
    fn runtime(&self) -> MohrCoulomb {
        self.model()
    }
    fn surface(&self) -> impl Fn(f64) -> PqSurface + 'static {
        let s = self.pq_surface();
        move |_| s
    }
    /// Its yield surface is the Mohr–Coulomb envelope; a layer flowing with its
    /// non-associated flow stops at Davis's angle ([`super::davis`]).
    fn behaviour(&self) -> super::Behaviour {
        super::Behaviour::Granular(super::Friction {
            friction_angle: self.friction_angle,
            cohesion: self.cohesion,
            cone: None,
            repose: super::davis(self.friction_angle, self.dilatancy_angle, 0.0).0,
        })
    }
    fn field_mut(&mut self, name: &str) -> Option<&mut f64> {
        match name {
            "friction_angle" => Some(&mut self.friction_angle),
            "dilatancy_angle" => Some(&mut self.dilatancy_angle),
            "cohesion" => Some(&mut self.cohesion),
            _ => super::elastic_field(
                name,
                [
                    &mut self.youngs_modulus,
                    &mut self.poisson_ratio,
                    &mut self.density,
                ],
            ),
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::material::test_util::drive;

    fn params(phi: f64, psi: f64, c: f64) -> MohrCoulombParams {
        MohrCoulombParams {
            youngs_modulus: 3.5e5,
            poisson_ratio: 0.3,
            density: 2200.0,
            friction_angle: phi,
            dilatancy_angle: psi,
            cohesion: c,
        }
    }

    fn principal(s: Sym3) -> [f64; 3] {
        let m = [
            [s.xx as f64, s.xy as f64, s.xz as f64],
            [s.xy as f64, s.yy as f64, s.yz as f64],
            [s.xz as f64, s.yz as f64, s.zz as f64],
        ];
        let (mut v, _) = eigen_symmetric(m);
        v.sort_by(|a, b| b.total_cmp(a));
        v
    }

    fn diag(s: [f64; 3]) -> Sym3 {
        Sym3 {
            xx: s[0] as Real,
            yy: s[1] as Real,
            zz: s[2] as Real,
            ..Sym3::ZERO
        }
    }

    /// The model's return of the trial stress `trial` (a step with no strain rate or spin,
    /// whose elastic trial is the stress itself).
    fn returned(m: &MohrCoulomb, trial: Sym3) -> (Sym3, StressUpdate) {
        let mut s = trial;
        let u = m.update(&mut s, Sym3::ZERO, [0.0; 3], 0.0, 1e-3);
        (s, u)
    }

    /// A rotation (of the Euler angles a, b, c) applied to a diagonal stress.
    fn rotated(s: [f64; 3], (a, b, c): (f64, f64, f64)) -> Sym3 {
        let rz = |t: f64| {
            [
                [t.cos(), -t.sin(), 0.0],
                [t.sin(), t.cos(), 0.0],
                [0.0, 0.0, 1.0],
            ]
        };
        let rx = |t: f64| {
            [
                [1.0, 0.0, 0.0],
                [0.0, t.cos(), -t.sin()],
                [0.0, t.sin(), t.cos()],
            ]
        };
        let mul = |p: [[f64; 3]; 3], q: [[f64; 3]; 3]| -> [[f64; 3]; 3] {
            std::array::from_fn(|i| {
                std::array::from_fn(|j| (0..3).map(|k| p[i][k] * q[k][j]).sum())
            })
        };
        let q = mul(rz(a), mul(rx(b), rz(c)));
        let m: [[f64; 3]; 3] = std::array::from_fn(|i| {
            std::array::from_fn(|j| (0..3).map(|k| q[i][k] * s[k] * q[j][k]).sum())
        });
        Sym3 {
            xx: m[0][0] as Real,
            yy: m[1][1] as Real,
            zz: m[2][2] as Real,
            xy: m[0][1] as Real,
            xz: m[0][2] as Real,
            yz: m[1][2] as Real,
        }
    }

    fn close(a: f64, b: f64, tol: f64, what: &str) {
        assert!((a - b).abs() <= tol, "{what}: {a} vs {b}");
    }

    #[test]
    fn the_plane_eigen_solve_matches_the_jacobi_sweeps() {
        let mut seed = 5u64;
        let mut next = move || {
            seed = seed
                .wrapping_mul(6364136223846793005)
                .wrapping_add(1442695040888963407);
            ((seed >> 11) as f64 / (1u64 << 53) as f64) * 2.0 - 1.0
        };
        for case in 0..2000 {
            // stresses of a few kPa, some with a vanishing or a dominant shear
            let scale = 10f64.powi(case % 7 - 2) * 1e3;
            let (xx, yy, zz) = (scale * next(), scale * next(), scale * next());
            let xy = match case % 4 {
                0 => scale * next() * 1e-9,
                1 => scale * next() * 1e3,
                _ => scale * next(),
            };
            let a = [[xx, xy, 0.0], [xy, yy, 0.0], [0.0, 0.0, zz]];
            let (lp, vp) = eigen_plane(a);
            let (lj, _) = eigen_jacobi(a);
            let norm = xx.abs() + yy.abs() + zz.abs() + 2.0 * xy.abs();
            let (mut sp, mut sj) = (lp, lj);
            sp.sort_by(f64::total_cmp);
            sj.sort_by(f64::total_cmp);
            for k in 0..3 {
                assert!(
                    (sp[k] - sj[k]).abs() <= 1e-13 * norm,
                    "{a:?}: {lp:?} vs {lj:?}"
                );
            }
            // V diag(λ) Vᵀ = A, and z stays a principal direction exactly
            for i in 0..3 {
                for j in 0..3 {
                    let r: f64 = (0..3).map(|k| vp[i][k] * lp[k] * vp[j][k]).sum();
                    assert!((r - a[i][j]).abs() <= 1e-13 * norm, "{a:?}: entry {i}{j}");
                }
            }
            assert_eq!(lp[2], zz);
        }
    }

    /// A stress past one face returns onto it along the plastic potential's normal: the
    /// plastic strain increment C⁻¹(σ_tr − σ) is parallel to m = (1 + sin ψ, 0, −(1 − sin ψ))
    /// (no intermediate principal plastic strain, and the dilatancy Δε_v/Δε_1 = 2 sin ψ/(1 + sin ψ)),
    /// with f = 0 after it, also when the stress is given in rotated axes.
    #[test]
    fn a_stress_past_a_face_returns_onto_it_along_the_potentials_normal() {
        for (phi, psi, c) in [(30.0, 0.0, 0.0), (35.0, 10.0, 200.0), (20.0, 20.0, 500.0)] {
            let m = params(phi, psi, c).model();
            let trial = [-1000.0, -3000.0, -9000.0];
            for axes in [(0.0, 0.0, 0.0), (0.3, 1.1, -0.7)] {
                let (s, u) = returned(&m, rotated(trial, axes));
                let r = principal(s);
                let scale = 1e-4 * 9000.0;
                close(m.plane(r, A), 0.0, scale, "f after the return");
                assert!(r[0] > r[1] && r[1] > r[2], "still a face: {r:?}");
                // C⁻¹ Δσ with Δσ = σ_tr − σ in principal values
                let d: [f64; 3] = std::array::from_fn(|k| trial[k] - r[k]);
                let mean = (d[0] + d[1] + d[2]) / 3.0;
                let eps = d.map(|x| (x - mean) / (2.0 * m.g) + mean / (3.0 * m.k));
                let sin_psi = psi.to_radians().sin();
                let expected = [1.0 + sin_psi, 0.0, -(1.0 - sin_psi)];
                let lambda = eps[0] / expected[0];
                assert!(lambda > 0.0);
                for k in 0..3 {
                    close(eps[k], lambda * expected[k], 2e-3 * eps[0].abs(), "normal");
                }
                assert!(u.plastic_strain > 0.0 && u.dissipation > 0.0);
            }
        }
    }

    /// A stress near triaxial compression (σ1 ≈ σ2) past both faces that meet there returns
    /// onto their edge: σ1 = σ2 and both planes' f = 0; likewise near triaxial extension
    /// (σ2 ≈ σ3).
    #[test]
    fn a_stress_near_an_edge_returns_onto_the_edge() {
        for (phi, psi, c) in [(30.0, 0.0, 0.0), (35.0, 10.0, 300.0)] {
            let m = params(phi, psi, c).model();
            let tol = 1e-4 * 8000.0;
            // compression: the axial stress σ3 far below two nearly equal lateral ones
            let (s, _) = returned(&m, rotated([-1000.0, -1100.0, -8000.0], (0.2, 0.4, 0.1)));
            let r = principal(s);
            close(r[0], r[1], tol, "σ1 = σ2");
            close(m.plane(r, A), 0.0, tol, "f_A");
            close(m.plane(r, B), 0.0, tol, "f_B");
            // extension: one stress far above two nearly equal ones
            let (s, _) = returned(&m, diag([1000.0, -8000.0, -8100.0]));
            let r = principal(s);
            close(r[1], r[2], tol, "σ2 = σ3");
            close(m.plane(r, A), 0.0, tol, "f_A");
            close(m.plane(r, C), 0.0, tol, "f_C");
        }
    }

    /// A stress in tension past the apex returns to it: σ = c cot φ I (zero for c = 0).
    #[test]
    fn a_stress_past_the_apex_returns_to_the_apex() {
        for c in [0.0, 400.0] {
            let m = params(30.0, 5.0, c).model();
            let apex = c / 30f64.to_radians().tan();
            let (s, u) = returned(&m, rotated([5000.0, 3000.0, 2000.0], (0.5, 0.2, 0.9)));
            for x in [s.xx, s.yy, s.zz] {
                close(x as f64, apex, 1e-3 * (1.0 + apex), "apex");
            }
            for x in [s.xy, s.xz, s.yz] {
                close(x as f64, 0.0, 1e-3 * (1.0 + apex), "no shear at the apex");
            }
            // the plastic work σ:Δε_p at the apex: the apex stress times the plastic volume
            // change, zero for a cohesionless apex (σ = 0)
            if c > 0.0 {
                assert!(u.dissipation > 0.0, "{}", u.dissipation);
            } else {
                assert!(u.dissipation.abs() < 1e-9, "{}", u.dissipation);
            }
        }
    }

    /// Many trial stresses, inside and outside: a stress inside is left exactly as it is, one
    /// outside ends on the surface (the largest f over every ordering is zero), in 3D and in
    /// plane strain (Sym2, whose zz is a principal stress).
    #[test]
    fn every_return_ends_on_the_surface_and_a_stress_inside_is_left_alone() {
        let mut seed = 11u64;
        let mut next = || {
            seed = seed
                .wrapping_mul(6_364_136_223_846_793_005)
                .wrapping_add(1_442_695_040_888_963_407);
            (seed >> 11) as f64 / (1u64 << 53) as f64 * 2.0 - 1.0
        };
        let (mut inside, mut outside) = (0, 0);
        for (phi, psi, c) in [(30.0, 0.0, 0.0), (40.0, 15.0, 800.0), (0.0, 0.0, 1500.0)] {
            let m = params(phi, psi, c).model();
            for _ in 0..400 {
                let trial = Sym3 {
                    xx: (4000.0 * next() - 3000.0) as Real,
                    yy: (4000.0 * next() - 3000.0) as Real,
                    zz: (4000.0 * next() - 3000.0) as Real,
                    xy: (1500.0 * next()) as Real,
                    xz: (1500.0 * next()) as Real,
                    yz: (1500.0 * next()) as Real,
                };
                let f = m.yield_function(principal(trial));
                let (s, u) = returned(&m, trial);
                let scale = 1e-4 * 8000.0;
                if f <= 0.0 {
                    inside += 1;
                    assert_eq!(s, trial);
                    assert_eq!(u.plastic_strain, 0.0);
                } else {
                    outside += 1;
                    close(
                        m.yield_function(principal(s)),
                        0.0,
                        scale,
                        "f after the return",
                    );
                }
                // plane strain
                let t2 = in_plane(trial);
                let mut s2 = t2;
                m.update(&mut s2, Sym2::ZERO, 0.0, 0.0, 1e-3);
                let f2 = m.yield_function(principal(plane(t2)));
                if f2 <= 0.0 {
                    assert_eq!(s2, t2);
                } else {
                    close(m.yield_function(principal(plane(s2))), 0.0, scale, "2D");
                }
            }
        }
        assert!(inside > 100 && outside > 100, "{inside} {outside}");
    }

    /// Simple shear under a confining pressure σ_n, in plane strain and in 3D, with ψ = 0
    /// (no dilation, so the kinematic constraint builds no pressure): the shear stress
    /// settles at the strength τ = c cos φ + σ_n sin φ (the Mohr circle of radius τ about
    /// σ_n touching the envelope, the out-of-plane stress the intermediate one). A layer
    /// flowing so stops at Davis's angle atan(sin φ), the repose angle of [`Kind::behaviour`].
    #[test]
    fn plane_strain_simple_shear_settles_at_c_cos_phi_plus_sigma_n_sin_phi() {
        for (phi, c) in [(30.0, 0.0), (25.0, 300.0), (40.0, 100.0)] {
            let m = params(phi, 0.0, c).model();
            let sigma_n = 2000.0;
            let strength = c * phi.to_radians().cos() + sigma_n * phi.to_radians().sin();
            let shear = [[0.0, 1.0, 0.0], [0.0, 0.0, 0.0], [0.0, 0.0, 0.0]];
            let (s, ep, _) = drive(&m, Sym3::iso(-sigma_n as Real), shear, 1e-4, 400, |_, _| {});
            close(s.xy.abs() as f64, strength, 3e-3 * strength, "3D τ");
            assert!(ep > 0.0);
            let g = crate::math::Mat2::from_cols(
                crate::math::Vec2::new(0.0, 0.0),
                crate::math::Vec2::new(1.0, 0.0),
            );
            let (rate, spin) = <crate::math::D2 as crate::math::Dim>::rate_and_spin(g);
            let mut s2 = Sym2::iso(-sigma_n as Real);
            for _ in 0..400 {
                m.update(&mut s2, rate, spin, 0.0, 1e-4);
            }
            close(
                s2.xy.abs() as f64,
                strength,
                3e-3 * strength,
                "plane strain τ",
            );
            if c == 0.0 {
                // a cohesionless layer flowing so stops at atan(sin φ): the repose angle its
                // heaps are judged against (Davis's, ψ = 0)
                let stop = (s2.xy.abs() as f64 / sigma_n).atan().to_degrees();
                let repose = super::super::Kind::behaviour(&params(phi, 0.0, c))
                    .friction()
                    .unwrap()
                    .repose;
                close(stop, repose, 0.05, "angle of repose");
            }
        }
    }

    /// The p–q lines are where the return puts triaxial states: a triaxial compression trial
    /// (σ1 = σ2 > σ3) on the upper line, an extension trial (σ1 > σ2 = σ3) on the lower one.
    #[test]
    fn triaxial_returns_land_on_the_pq_meridians() {
        for (phi, c) in [(30.0, 0.0), (35.0, 400.0)] {
            let p = params(phi, 0.0, c);
            let (m, surface) = (p.model(), p.pq_surface());
            let (low_slope, low_intercept) = surface.lower.unwrap();
            let (s, _) = returned(&m, diag([-2000.0, -2000.0, -9000.0]));
            let (pp, q) = crate::material::pq(s);
            close(
                q,
                surface.slope * pp + surface.intercept,
                1e-3 * q,
                "compression",
            );
            let (s, _) = returned(&m, diag([2000.0, -6000.0, -6000.0]));
            let (pp, q) = crate::material::pq(s);
            close(q, low_slope * pp + low_intercept, 1e-3 * q, "extension");
            assert!(surface.reached(pp, q));
        }
    }
}
