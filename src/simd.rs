//! Hot loops compiled a second time for wider vectors, the copy picked at run time where the
//! processor has them: the crate builds for the baseline x86-64 (four floats or sixteen bytes
//! to an instruction), and one binary serves every machine.

/// Defines `fn $name(args)` as `$body(args)`, compiled a second time with `$feature` (such as
/// `"avx"`: eight floats to an instruction instead of four) and run so where the processor has
/// it. The same operations in the same order, so the same bytes either way: keep fused
/// multiply-adds out (they round once where a product and a sum round twice). `$body` must be
/// `#[inline(always)]` to be compiled into the wider copy, and so must what it calls in its
/// hot loops; a closure it hands on is widened only where the compiler inlines it (speed,
/// never bytes). Each use keeps a test that both copies give the same result.
macro_rules! with_feature {
    ($feature:tt; $(#[$m:meta])* $vis:vis fn $name:ident($($a:ident: $t:ty),* $(,)?) $(-> $r:ty)? => $body:ident) => {
        $(#[$m])*
        $vis fn $name($($a: $t),*) $(-> $r)? {
            #[cfg(target_arch = "x86_64")]
            if std::arch::is_x86_feature_detected!($feature) {
                #[target_feature(enable = $feature)]
                fn wide($($a: $t),*) $(-> $r)? {
                    $body($($a),*)
                }
                // SAFETY: the processor has the feature, checked just above.
                return unsafe { wide($($a),*) };
            }
            $body($($a),*)
        }
    };
}

pub(crate) use with_feature;
