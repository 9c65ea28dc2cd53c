//! The boundary constraints of Eq. 10–11 as a variable layout: each vertex coordinate is either
//! an unknown of the system or fixed to a side of the target rectangle.
//!
//! Eq. 11 as printed keeps a side vertex's other coordinate unchanged (`v'_i = (0, v_iy)`), which
//! cannot hold when the height changes too; as DESIGN.md says, side vertices slide along their
//! side and only the coordinate across it is fixed. Corners are fixed at the target's corners.

use crate::image::Size;
use crate::mesh::Mesh;

/// Marks a coordinate that is not an unknown.
pub(crate) const FIXED: u32 = u32::MAX;

/// Which unknown each vertex coordinate and each triangle scale is.
#[derive(Clone, Debug, Default)]
pub(crate) struct Layout {
    /// Unknown index of each vertex's x', or [`FIXED`].
    pub x_var: Vec<u32>,
    /// Unknown index of each vertex's y', or [`FIXED`].
    pub y_var: Vec<u32>,
    /// Value of x' where fixed (unused otherwise).
    pub x_fixed: Vec<f64>,
    /// Value of y' where fixed.
    pub y_fixed: Vec<f64>,
    /// First scale unknown: `s_t` is unknown `s_base + t`.
    pub s_base: usize,
    /// Number of unknowns.
    pub n: usize,
}

impl Layout {
    pub fn new(mesh: &Mesh, target: Size) -> Layout {
        let (w, h) = (mesh.size().width as f64, mesh.size().height as f64);
        let (tw, th) = (target.width as f64, target.height as f64);
        let nv = mesh.vertices().len();
        let mut l = Layout {
            x_var: vec![FIXED; nv],
            y_var: vec![FIXED; nv],
            x_fixed: vec![0.0; nv],
            y_fixed: vec![0.0; nv],
            s_base: 0,
            n: 0,
        };
        let mut next = 0u32;
        for (i, (&p, &b)) in mesh.vertices().iter().zip(mesh.boundary()).enumerate() {
            if b.fixes_x() {
                l.x_fixed[i] = if p.x >= w { tw } else { 0.0 };
            } else {
                l.x_var[i] = next;
                next += 1;
            }
        }
        for (i, (&p, &b)) in mesh.vertices().iter().zip(mesh.boundary()).enumerate() {
            if b.fixes_y() {
                l.y_fixed[i] = if p.y >= h { th } else { 0.0 };
            } else {
                l.y_var[i] = next;
                next += 1;
            }
        }
        l.s_base = next as usize;
        l.n = next as usize + mesh.triangles().len();
        l
    }

    /// Number of free vertex coordinates (the paper's DOF).
    pub fn dof(&self) -> usize {
        self.s_base
    }
}
