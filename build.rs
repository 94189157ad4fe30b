//! Builds the C++ adapter in `cpp/` with CMake (OpenMesh, CGAL, Eigen3 from Debian) and
//! the `cxx` bridge of `src/ffi/mod.rs`, then links them.

use std::path::Path;

/// Files whose absence means a Debian package is missing.
const REQUIRED: &[(&str, &str)] = &[
    ("/usr/include/OpenMesh/Core/Mesh/TriMesh_ArrayKernelT.hh", "libopenmesh-dev"),
    ("/usr/include/CGAL/version.h", "libcgal-dev"),
    ("/usr/include/eigen3/Eigen/Core", "libeigen3-dev"),
    ("/usr/include/boost/version.hpp", "libboost-dev"),
    ("/usr/include/mpfr.h", "libmpfr-dev"),
];

fn require_system_packages() {
    let mut missing: Vec<&str> =
        REQUIRED.iter().filter(|(file, _)| !Path::new(file).exists()).map(|(_, pkg)| *pkg).collect();
    let has_gmp = ["/usr/include/gmp.h", "/usr/include/x86_64-linux-gnu/gmp.h", "/usr/include/aarch64-linux-gnu/gmp.h"]
        .iter()
        .any(|f| Path::new(f).exists());
    if !has_gmp {
        missing.push("libgmp-dev");
    }
    let has_cmake = std::env::var_os("PATH")
        .map(|paths| std::env::split_paths(&paths).any(|dir| dir.join("cmake").is_file()))
        .unwrap_or(false);
    if !has_cmake {
        missing.push("cmake");
    }
    if !missing.is_empty() {
        eprintln!(
            "\nasperity needs Debian packages that are not installed ({}): run `scripts/install-deps.sh` (or `make test`), then build again.\n",
            missing.join(", ")
        );
        std::process::exit(1);
    }
}

fn main() {
    println!("cargo:rerun-if-changed=build.rs");
    println!("cargo:rerun-if-changed=cpp");
    println!("cargo:rerun-if-changed=src/ffi/mod.rs");
    require_system_packages();

    // `make sanitize` sets ASPERITY_SANITIZE=address,undefined: the adapter and the bridge
    // are instrumented and every binary of the crate links the sanitizer runtimes.
    println!("cargo:rerun-if-env-changed=ASPERITY_SANITIZE");
    let sanitize = std::env::var("ASPERITY_SANITIZE").unwrap_or_default();

    // The C++ is always optimised: CGAL and OpenMesh are unusably slow in debug builds.
    let native = cmake::Config::new("cpp")
        .profile("Release")
        .define("ASPERITY_SANITIZE", &sanitize)
        .build_target("asperity_native")
        .build();

    let mut bridge = cxx_build::bridge("src/ffi/mod.rs");
    bridge
        .file("cpp/bridge/bridge.cc")
        .include("cpp/include")
        .std("c++17")
        .opt_level(2)
        .flag_if_supported("-Wno-unused-parameter");
    if !sanitize.is_empty() {
        bridge.flag(format!("-fsanitize={sanitize}")).flag("-fno-omit-frame-pointer").flag("-fno-sanitize-recover=all");
        println!("cargo:rustc-link-arg=-fsanitize={sanitize}");
    }
    bridge.compile("asperity_bridge");

    // The static adapter after the bridge that calls it, then the shared libraries it needs
    // (the sanitizer runtimes first: ASan wants to come first among the libraries loaded).
    println!("cargo:rustc-link-search=native={}/build", native.display());
    println!("cargo:rustc-link-lib=static=asperity_native");
    for (sanitizer, runtime) in [("address", "asan"), ("undefined", "ubsan")] {
        if sanitize.split(',').any(|s| s.trim() == sanitizer) {
            println!("cargo:rustc-link-lib=dylib={runtime}");
        }
    }
    for lib in ["OpenMeshTools", "OpenMeshCore", "gmp", "mpfr", "stdc++"] {
        println!("cargo:rustc-link-lib=dylib={lib}");
    }
}
