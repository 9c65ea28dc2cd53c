//! The three saliency levels of §5.1 (Fig. 6): the mesh is sampled per level, and content
//! enhancement (§5.4) sets a factor per level.

/// A saliency level `k` (the paper's `t_k0 ≤ S < t_k1`).
#[derive(Copy, Clone, Debug, PartialEq, Eq, PartialOrd, Ord, Hash)]
pub enum SaliencyLevel {
    /// k = 1, `S ∈ [0, 0.15)`: empty background.
    Background = 1,
    /// k = 2, `S ∈ [0.15, 0.5)`: context (light layers, surroundings of edges).
    Context = 2,
    /// k = 3, `S ∈ [0.5, 1]`: the marks that matter.
    Salient = 3,
}

impl SaliencyLevel {
    /// All levels, in order of `k`.
    pub const ALL: [SaliencyLevel; 3] = [
        SaliencyLevel::Background,
        SaliencyLevel::Context,
        SaliencyLevel::Salient,
    ];

    /// The lower bound `t_k0` of each level.
    pub const fn lower_bound(self) -> f32 {
        match self {
            SaliencyLevel::Background => 0.0,
            SaliencyLevel::Context => 0.15,
            SaliencyLevel::Salient => 0.5,
        }
    }

    /// The level of a saliency value.
    #[inline]
    pub fn of(s: f32) -> SaliencyLevel {
        if s >= 0.5 {
            SaliencyLevel::Salient
        } else if s >= 0.15 {
            SaliencyLevel::Context
        } else {
            SaliencyLevel::Background
        }
    }

    /// `k - 1`, for indexing per-level arrays.
    pub const fn index(self) -> usize {
        self as usize - 1
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn bounds_match_the_paper() {
        assert_eq!(SaliencyLevel::of(0.0), SaliencyLevel::Background);
        assert_eq!(SaliencyLevel::of(0.149), SaliencyLevel::Background);
        assert_eq!(SaliencyLevel::of(0.15), SaliencyLevel::Context);
        assert_eq!(SaliencyLevel::of(0.499), SaliencyLevel::Context);
        assert_eq!(SaliencyLevel::of(0.5), SaliencyLevel::Salient);
        assert_eq!(SaliencyLevel::of(1.0), SaliencyLevel::Salient);
        for l in SaliencyLevel::ALL {
            assert_eq!(SaliencyLevel::of(l.lower_bound()), l);
        }
    }
}
