//! The boundary constraints of Eq. 10–11 as a variable layout: each vertex coordinate is either
//! an unknown of the system or fixed to a side of the target rectangle.
//!
//! Eq. 11 as printed keeps a side vertex's other coordinate unchanged (`v'_i = (0, v_iy)`), which
//! cannot hold when the height changes too; as DESIGN.md says, side vertices slide along their
//! side and only the coordinate across it is fixed. Corners are fixed at the target's corners.

use crate::image::Size;
use crate::mesh::Mesh;
use glam::DVec2;

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
    /// Unknown index of each triangle's scale `s_t`, or [`FIXED`] for a triangle whose corners
    /// are all fixed (it takes no part in the system).
    pub s_var: Vec<u32>,
    /// Free vertex coordinates (the paper's DOF).
    pub dof: usize,
    /// Number of unknowns.
    pub n: usize,
}

impl Layout {
    /// Every vertex free but for the boundary constraints.
    pub fn new(mesh: &Mesh, target: Size) -> Layout {
        Layout::with_fixed(mesh, target, &[])
    }

    /// Like [`Layout::new`], but vertex `i` with `fixed[i] = Some(p)` is held at `p` (a local
    /// update keeps everything outside the changed region where the last frame put it). An
    /// empty `fixed` fixes nothing.
    pub fn with_fixed(mesh: &Mesh, target: Size, fixed: &[Option<DVec2>]) -> Layout {
        let (w, h) = (mesh.size().width as f64, mesh.size().height as f64);
        let (tw, th) = (target.width as f64, target.height as f64);
        let nv = mesh.vertices().len();
        let nt = mesh.triangles().len();
        let mut l = Layout {
            x_var: vec![FIXED; nv],
            y_var: vec![FIXED; nv],
            x_fixed: vec![0.0; nv],
            y_fixed: vec![0.0; nv],
            s_var: vec![FIXED; nt],
            dof: 0,
            n: 0,
        };
        let held = |i: usize| fixed.get(i).copied().flatten();
        let mut next = 0u32;
        for (i, (&p, &b)) in mesh.vertices().iter().zip(mesh.boundary()).enumerate() {
            if b.fixes_x() {
                l.x_fixed[i] = if p.x >= w { tw } else { 0.0 };
            } else if let Some(q) = held(i) {
                l.x_fixed[i] = q.x;
            } else {
                l.x_var[i] = next;
                next += 1;
            }
        }
        for (i, (&p, &b)) in mesh.vertices().iter().zip(mesh.boundary()).enumerate() {
            if b.fixes_y() {
                l.y_fixed[i] = if p.y >= h { th } else { 0.0 };
            } else if let Some(q) = held(i) {
                l.y_fixed[i] = q.y;
            } else {
                l.y_var[i] = next;
                next += 1;
            }
        }
        l.dof = next as usize;
        for (t, tri) in mesh.triangles().iter().enumerate() {
            let active = tri
                .iter()
                .any(|&v| l.x_var[v as usize] != FIXED || l.y_var[v as usize] != FIXED);
            if active {
                l.s_var[t] = next;
                next += 1;
            }
        }
        l.n = next as usize;
        l
    }

    /// Number of free vertex coordinates (the paper's DOF).
    pub fn dof(&self) -> usize {
        self.dof
    }

    /// A hash of the pattern of unknowns (which coordinates and scales are free), with the
    /// mesh topology: equal keys mean the same sparsity pattern.
    pub fn pattern_key(&self, mesh: &Mesh) -> u64 {
        use std::hash::{Hash, Hasher};
        let mut h = std::collections::hash_map::DefaultHasher::new();
        mesh.triangles().hash(&mut h);
        self.x_var.hash(&mut h);
        self.y_var.hash(&mut h);
        self.s_var.hash(&mut h);
        h.finish()
    }
}
