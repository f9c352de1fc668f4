#include "comm/CellGraph.hpp"

#include <metis.h>

#include <algorithm>
#include <stdexcept>
#include <unordered_map>

#include "core/CellKeys.hpp"

namespace ringdem {

std::vector<std::int32_t> CellGraph::partition(const std::vector<CellLoad>& cells, int n_parts) {
  const auto n = static_cast<idx_t>(cells.size());
  std::vector<std::int32_t> part(cells.size(), 0);
  if (n <= n_parts) {
    for (idx_t v = 0; v < n; ++v)
      part[static_cast<std::size_t>(v)] = static_cast<std::int32_t>(v);
    return part;
  }
  std::unordered_map<std::uint64_t, idx_t> index;
  for (idx_t v = 0; v < n; ++v)
    index.emplace(cells[static_cast<std::size_t>(v)].key, v);
  std::vector<idx_t> xadj{0}, adjncy, adjwgt, vwgt;
  for (idx_t v = 0; v < n; ++v) {
    const CellLoad& b = cells[static_cast<std::size_t>(v)];
    vwgt.push_back(static_cast<idx_t>(vertex_weight(b)));
    cell_keys::for_each_neighbour(b.key, [&](std::uint64_t other) {
      const auto it = index.find(other);
      if (it == index.end() || it->second == v) return;
      const CellLoad& o = cells[static_cast<std::size_t>(it->second)];
      adjncy.push_back(it->second);
      // Interactions across the face scale with the smaller population of the two.
      adjwgt.push_back(static_cast<idx_t>(std::min(b.particles, o.particles)) + 1);
    });
    xadj.push_back(static_cast<idx_t>(adjncy.size()));
  }
  idx_t ncon = 1, nparts = n_parts, objval = 0;
  idx_t options[METIS_NOPTIONS];
  METIS_SetDefaultOptions(options);
  options[METIS_OPTION_SEED] = 1;
  std::vector<idx_t> out(static_cast<std::size_t>(n));
  idx_t vertices = n;
  const int status =
      METIS_PartGraphKway(&vertices, &ncon, xadj.data(), adjncy.data(), vwgt.data(), nullptr,
                          adjwgt.data(), &nparts, nullptr, nullptr, options, &objval, out.data());
  if (status != METIS_OK) throw std::runtime_error("METIS_PartGraphKway failed");
  for (idx_t v = 0; v < n; ++v)
    part[static_cast<std::size_t>(v)] = static_cast<std::int32_t>(out[static_cast<std::size_t>(v)]);
  return part;
}

}  // namespace ringdem
