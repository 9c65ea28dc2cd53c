//! Hot loops compiled a second time for wider vectors, the copy picked at run time where the
//! processor has them: the crate builds for the baseline x86-64 (four floats or sixteen bytes
//! to an instruction), and one binary serves every machine.

/// Defines `fn $name(args)` running the block, compiled twice: as `$body` (`#[inline(always)]`,
/// for the baseline, and callable on its own so that tests can compare the two) and a second
/// time with `$feature` (such as `"avx"`: eight floats to an instruction instead of four), run
/// where the processor has it. The same operations in the same order, so the same bytes
/// either way: keep fused multiply-adds out (they round once where a product and a sum round
/// twice). What the block calls in its hot loops must be `#[inline(always)]` to be widened
/// too; a closure it hands on is widened only where the compiler inlines it (speed, never
/// bytes). Each use keeps a test that both copies give the same result.
macro_rules! with_feature {
    ($feature:tt; $(#[$m:meta])* $vis:vis fn $name:ident($($a:ident: $t:ty),* $(,)?)
        $(-> $r:ty)? => $body:ident $block:block) => {
        #[inline(always)]
        fn $body($($a: $t),*) $(-> $r)? $block

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
