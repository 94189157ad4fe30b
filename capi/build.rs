//! Generates the C++ side of the bridge. When `ASPERITY_HEADER_DIR` is set (by the CMake
//! package build in `cpp/`), the generated header and `rust/cxx.h` are copied there as
//! `asperity/bridge.rs.h` and `rust/cxx.h`, for installation (with the package's headers,
//! among them `asperity/progress.hpp`, which the bridge includes).

use std::path::{Path, PathBuf};

fn main() {
    println!("cargo:rerun-if-changed=src/lib.rs");
    println!("cargo:rerun-if-changed=../cpp/package/progress.hpp");
    println!("cargo:rerun-if-env-changed=ASPERITY_HEADER_DIR");
    // The bridge includes the C++ side's own type (the progress callback) as its users
    // do: <asperity/progress.hpp>, staged here from cpp/package/.
    let staged = PathBuf::from(std::env::var_os("OUT_DIR").expect("cargo sets OUT_DIR")).join("package-include");
    copy(Path::new("../cpp/package/progress.hpp"), &staged.join("asperity/progress.hpp"));
    cxx_build::bridge("src/lib.rs").std("c++17").include(&staged).compile("asperity_cxx_bridge");
    let Some(dest) = std::env::var_os("ASPERITY_HEADER_DIR").map(PathBuf::from) else { return };
    println!("cargo:rerun-if-changed={}", dest.join("asperity/bridge.rs.h").display());
    let generated = PathBuf::from(std::env::var_os("OUT_DIR").expect("cargo sets OUT_DIR")).join("cxxbridge/include");
    copy(&generated.join("asperity-cxx/src/lib.rs.h"), &dest.join("asperity/bridge.rs.h"));
    copy(&generated.join("rust/cxx.h"), &dest.join("rust/cxx.h"));
}

fn copy(from: &Path, to: &Path) {
    let parent = to.parent().expect("a file path has a parent");
    std::fs::create_dir_all(parent).unwrap_or_else(|e| panic!("creating {}: {e}", parent.display()));
    // Copy the bytes (the generated paths may be symbolic links).
    let bytes = std::fs::read(from).unwrap_or_else(|e| panic!("reading {}: {e}", from.display()));
    std::fs::write(to, bytes).unwrap_or_else(|e| panic!("writing {}: {e}", to.display()));
}
