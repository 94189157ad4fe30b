// asperity — the native C++ API in one include.
#pragma once
#include "asperity/cgal_ops.hpp"
#include "asperity/halfedge_mesh.hpp"
#include "asperity/reference_decimators.hpp"
