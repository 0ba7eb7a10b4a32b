// libFuzzer harness: the uploaded vector-field parser (compute/src/flow/field.cpp parse_field, the body of
// POST /api/v1/flow and `trailscope flow --field`; format proto/flow_field.md). Besides a clean refusal,
// what the flow map relies on is checked: one sector holding width x height cells of finite sums whose
// weights are >= 0 (the streamline tracer divides by them), and a geographic grid with a positive,
// finite cell.
#include <cmath>

#include "fuzz_support.hpp"
#include "trailscope/flow/field.hpp"

using namespace trailscope;

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  try {
    const flow::VectorField f = flow::parse_field(std::string(fuzz::bytes_of(data, size)));
    const flow::Grid& g = f.grid;
    if (g.nx < 2 || g.ny < 2 || g.nx > limits::kMaxFlowGridCells || g.ny > limits::kMaxFlowGridCells)
      std::abort();
    if (f.sectors.size() != 1 || f.by_heading) std::abort();
    if (!(std::isfinite(g.cell) && g.cell > 0 && std::isfinite(g.x0) && std::isfinite(g.y0))) std::abort();
    const flow::SectorField& s = f.sectors[0];
    if (s.sx.size() != g.cells() || s.sy.size() != g.cells() || s.w.size() != g.cells()) std::abort();
    for (std::size_t k = 0; k < g.cells(); ++k)
      if (!(std::isfinite(s.sx[k]) && std::isfinite(s.sy[k]) && std::isfinite(s.w[k]) && s.w[k] >= 0))
        std::abort();
    const std::vector<float> t = flow::total_traffic(f);
    if (t.size() != g.cells()) std::abort();
  } catch (const Error& e) {
    fuzz::refuse(e);
  }
  return 0;
}
