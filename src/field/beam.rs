//! A small Euler–Bernoulli beam rotor ([`BeamRotor`]) that builds a [`RotorModel`] with six
//! degrees of freedom per node in ROSS's order, for tests, examples and students. Real
//! machines come from a proper finite-element model (ROSS, for one); this builder is not one.

use crate::error::FieldError;
use faer::Mat;

use super::model::{BearingSite, RotorModel};
use crate::error::{Error, Result};

/// A rigid disk at a node: mass, polar and diametral moments of inertia.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Disk {
    /// The node it sits at.
    pub node: usize,
    /// Mass (kg).
    pub mass: f64,
    /// Polar moment of inertia `I_p` (kg·m²).
    pub polar: f64,
    /// Diametral moment of inertia `I_d` (kg·m²).
    pub diametral: f64,
}

/// A uniform round shaft of Euler–Bernoulli beam elements with rigid disks, free (no bearings).
///
/// Degrees of freedom per node `x, y, z, alpha, beta, theta` (ROSS 3.x): lateral
/// displacements, axial displacement, rotations about x and y, torsion. Bending in the x–z
/// plane uses `(x, β)` with `β = dx/dz`, in the y–z plane `(y, α)` with `α = −dy/dz`; cubic
/// shape functions and consistent mass (no rotary inertia or shear of the shaft); axial rod
/// and torsion with linear shape functions. A disk adds `m` on `x, y, z`, `I_d` on `α, β`,
/// `I_p` on `θ`, and the gyroscopic coupling `G[α][β] = I_p`, `G[β][α] = −I_p` (ROSS's sign).
/// Axial and torsional stiffnesses are 10⁵–10⁹ times the bending ones at the nodes, as in a
/// ROSS model, so the unknowns of a field identification span many orders of magnitude.
#[derive(Debug, Clone, PartialEq)]
pub struct BeamRotor {
    /// Element lengths (m); the shaft has one node more than elements.
    pub element_lengths: Vec<f64>,
    /// Shaft diameter (m).
    pub diameter: f64,
    /// Density (kg/m³).
    pub density: f64,
    /// Young's modulus (Pa).
    pub young: f64,
    /// Poisson's ratio (for the shear modulus of torsion).
    pub poisson: f64,
    /// The disks.
    pub disks: Vec<Disk>,
    /// The bearings (their nodes; their coefficients are what field identification finds).
    pub bearings: Vec<BearingSite>,
}

/// Degrees of freedom per node and their names, ROSS's order.
pub const DOF_NAMES: [&str; 6] = ["x", "y", "z", "alpha", "beta", "theta"];

impl BeamRotor {
    /// The free rotor's `M`, `K`, `G` (no damping) as a [`RotorModel`].
    ///
    /// # Errors
    /// [`FieldError::Input`] for no elements, a length, diameter, density or modulus that is
    /// not finite and positive, or a disk past the last node; as [`RotorModel::new`].
    ///
    /// # Examples
    /// ```
    /// use bearing_ident::field::{BeamRotor, BearingSite};
    /// let rotor = BeamRotor {
    ///     element_lengths: vec![0.2; 4],
    ///     diameter: 0.05,
    ///     density: 7850.0,
    ///     young: 2.1e11,
    ///     poisson: 0.3,
    ///     disks: vec![],
    ///     bearings: vec![BearingSite::new("brg0", 0), BearingSite::new("brg1", 4)],
    /// }
    /// .model()?;
    /// assert_eq!(rotor.dofs(), 30);
    /// // The shaft's mass, ρ·A·L, on every translation.
    /// let m: f64 = (0..5).map(|a| (0..5).map(|b| rotor.mass()[(6 * a, 6 * b)]).sum::<f64>()).sum();
    /// assert!((m - 7850.0 * std::f64::consts::PI * 0.025f64.powi(2) * 0.8).abs() < 1e-9);
    /// # Ok::<(), bearing_ident::Error>(())
    /// ```
    pub fn model(&self) -> Result<RotorModel> {
        let bad = |message: String| Err(Error::Field(FieldError::Input { message }));
        if self.element_lengths.is_empty() {
            return bad("the beam has no elements".to_owned());
        }
        let positive = |v: f64| v.is_finite() && v > 0.0;
        if !(self.element_lengths.iter().all(|&l| positive(l))
            && positive(self.diameter)
            && positive(self.density)
            && positive(self.young)
            && self.poisson.is_finite()
            && self.poisson > -1.0)
        {
            return bad("beam lengths, diameter, density and modulus must be positive".to_owned());
        }
        let nodes = self.element_lengths.len() + 1;
        let n = 6 * nodes;
        let mut m = Mat::<f64>::zeros(n, n);
        let mut k = Mat::<f64>::zeros(n, n);
        let mut g = Mat::<f64>::zeros(n, n);
        let r = self.diameter / 2.0;
        let area = std::f64::consts::PI * r * r;
        let inertia = area * r * r / 4.0;
        let polar = 2.0 * inertia;
        let shear = self.young / (2.0 * (1.0 + self.poisson));
        for (e, &l) in self.element_lengths.iter().enumerate() {
            let ei = self.young * inertia / l.powi(3);
            let kb = [
                [12.0, 6.0 * l, -12.0, 6.0 * l],
                [6.0 * l, 4.0 * l * l, -6.0 * l, 2.0 * l * l],
                [-12.0, -6.0 * l, 12.0, -6.0 * l],
                [6.0 * l, 2.0 * l * l, -6.0 * l, 4.0 * l * l],
            ];
            let rho = self.density * area * l / 420.0;
            let mb = [
                [156.0, 22.0 * l, 54.0, -13.0 * l],
                [22.0 * l, 4.0 * l * l, 13.0 * l, -3.0 * l * l],
                [54.0, 13.0 * l, 156.0, -22.0 * l],
                [-13.0 * l, -3.0 * l * l, -22.0 * l, 4.0 * l * l],
            ];
            let (a, b) = (6 * e, 6 * (e + 1));
            // x–z plane: (x, β); y–z plane: (y, α) with α = −dy/dz (signs of the rotations).
            for (dofs, sign) in [
                ([a, a + 4, b, b + 4], 1.0),
                ([a + 1, a + 3, b + 1, b + 3], -1.0),
            ] {
                let s = |i: usize| if i % 2 == 1 { sign } else { 1.0 };
                for i in 0..4 {
                    for j in 0..4 {
                        k[(dofs[i], dofs[j])] += ei * s(i) * s(j) * kb[i][j];
                        m[(dofs[i], dofs[j])] += rho * s(i) * s(j) * mb[i][j];
                    }
                }
            }
            // Axial (z) and torsion (θ): two-node rods.
            for (dof, stiff, mass) in [
                (2, self.young * area / l, self.density * area * l / 6.0),
                (5, shear * polar / l, self.density * polar * l / 6.0),
            ] {
                let (i, j) = (a + dof, b + dof);
                k[(i, i)] += stiff;
                k[(j, j)] += stiff;
                k[(i, j)] -= stiff;
                k[(j, i)] -= stiff;
                m[(i, i)] += 2.0 * mass;
                m[(j, j)] += 2.0 * mass;
                m[(i, j)] += mass;
                m[(j, i)] += mass;
            }
        }
        for d in &self.disks {
            if d.node >= nodes {
                return bad(format!(
                    "a disk at node {}, but the beam has nodes 0–{}",
                    d.node,
                    nodes - 1
                ));
            }
            let a = 6 * d.node;
            for (dof, v) in [
                (0, d.mass),
                (1, d.mass),
                (2, d.mass),
                (3, d.diametral),
                (4, d.diametral),
                (5, d.polar),
            ] {
                m[(a + dof, a + dof)] += v;
            }
            g[(a + 3, a + 4)] += d.polar;
            g[(a + 4, a + 3)] -= d.polar;
        }
        RotorModel::new(
            6,
            DOF_NAMES.iter().map(|s| (*s).to_owned()).collect(),
            m,
            k,
            g,
            None,
            self.bearings.clone(),
        )
    }
}
