//! Kinematics of the axis group (pick_and_place.md §2.1): real axes A1 … A6 from the Cartesian
//! TCP pose X, Y, Z, A, B, C and back. Aux1 is separate and not transformed.

/// Forward/inverse transformation between the Cartesian pose and the real axes A1 … A6.
pub trait Kinematics: Send + std::fmt::Debug {
    /// Real axes A1 … A6 for a Cartesian pose X, Y, Z, A, B, C.
    fn inverse(&self, cartesian: &[f64; 6]) -> [f64; 6];
    /// Cartesian pose for real axes A1 … A6.
    fn forward(&self, joints: &[f64; 6]) -> [f64; 6];
}

/// The simulator's kinematics (proposal §2.1): A1 = X, A2 = Y, A3 = Z, A4 = A, A5 = B, A6 = C.
#[derive(Clone, Copy, Debug, Default)]
pub struct IdentityKinematics;

impl Kinematics for IdentityKinematics {
    fn inverse(&self, cartesian: &[f64; 6]) -> [f64; 6] {
        *cartesian
    }
    fn forward(&self, joints: &[f64; 6]) -> [f64; 6] {
        *joints
    }
}
