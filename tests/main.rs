//! asperity's integration tests, in one binary so the C++ libraries are linked once.

mod common;
mod ffi;
