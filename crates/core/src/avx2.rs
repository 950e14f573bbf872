//! Run-time dispatch to an AVX2 compilation of a loop: the crate's one place that checks the
//! processor and calls code compiled for a feature it may lack.

/// Defines `fn $name(args) -> ret` that runs `$body(args)` compiled for AVX2 where the
/// processor has it (checked at run time) and as compiled for the baseline elsewhere.
///
/// `$body` is meant to be `#[inline(always)]`, so that each compilation holds its own copy
/// with its loops widened to the vectors it has. The two give the same bits wherever `$body`
/// uses integers and IEEE operations rounded once (none fused, as neither compilation fuses
/// a multiply and an add on its own): each caller's docs say so, and its tests compare them.
macro_rules! avx2_dispatch {
    (
        $(#[$meta:meta])*
        $vis:vis fn $name:ident($($arg:ident: $ty:ty),* $(,)?) $(-> $ret:ty)? => $body:path;
    ) => {
        $(#[$meta])*
        #[allow(unsafe_code)]
        $vis fn $name($($arg: $ty),*) $(-> $ret)? {
            // `$body` compiled for AVX2.
            #[cfg(target_arch = "x86_64")]
            #[target_feature(enable = "avx2")]
            fn avx2($($arg: $ty),*) $(-> $ret)? {
                $body($($arg),*)
            }
            #[cfg(target_arch = "x86_64")]
            if std::arch::is_x86_feature_detected!("avx2") {
                // SAFETY: the processor has AVX2, checked just above.
                return unsafe { avx2($($arg),*) };
            }
            $body($($arg),*)
        }
    };
}

pub(crate) use avx2_dispatch;
