// libasperity.so: the static package library (Rust pipeline, OpenMesh/CGAL adapter, cxx
// bridge) linked whole into a shared object, for programs that link dynamically
// (`pkg-config --cflags --libs asperity`). Its ABI is the cxx bridge's functions that the
// installed headers call (asperity/bridge.rs.h); the soname's number (libasperity.so.0)
// changes when they change incompatibly. This file only gives the target a source.
extern "C" const char* asperity_shared_library_version() { return ASPERITY_VERSION; }
