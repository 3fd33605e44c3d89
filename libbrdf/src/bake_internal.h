#pragma once
// Internal: the bake with a choice of node evaluation (bake.cpp), for bench/bench_bake.cpp, which
// times both paths in one run.
#include "libbrdf/lut.h"

namespace libbrdf::detail {

enum class BakeNodePath {
  span,      // each row of nodes as one span: Model::evaluate_many (SIMD geometry and factors)
  per_node,  // node by node through Model::evaluate (the path before the span API)
};

// bake(r) (lut.h) with the given node path; bake(r) is bake(r, BakeNodePath::span).
Lut bake(const BakeRequest& r, BakeNodePath path);

}  // namespace libbrdf::detail
