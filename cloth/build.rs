//! Which SIMD levels the machine building this crate has, as the cfgs
//! `symlab_avx2` and `symlab_avx512`, for the tests that run every level
//! against the portable one (`integrator_core::simd`): a level this machine
//! lacks is `#[ignore]`d there with the reason, so the test log shows which
//! levels ran (a test can only be ignored when it is built). Nothing else
//! reads them: the kernels choose their level when they run.

fn main() {
    println!("cargo::rustc-check-cfg=cfg(symlab_avx2, symlab_avx512)");
    println!("cargo::rerun-if-changed=build.rs");
    // Only when the tests run where they are built.
    let native = std::env::var("HOST").ok() == std::env::var("TARGET").ok();
    #[cfg(target_arch = "x86_64")]
    if native {
        if std::arch::is_x86_feature_detected!("avx2") {
            println!("cargo::rustc-cfg=symlab_avx2");
        }
        if std::arch::is_x86_feature_detected!("avx512f") {
            println!("cargo::rustc-cfg=symlab_avx512");
        }
    }
    #[cfg(not(target_arch = "x86_64"))]
    let _ = native;
}
