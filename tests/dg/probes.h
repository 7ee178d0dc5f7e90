#ifndef ddfem_tests_dg_probes_h
#define ddfem_tests_dg_probes_h

#include <deal.II/base/tensor.h>

#include <nlohmann/json.hpp>

#include <vector>

namespace ddfem::testing
{
  /// The displacements of the probes of @p summary (a run's summary.json).
  inline std::vector<dealii::Tensor<1, 3>>
  probe_displacements(const nlohmann::json &summary)
  {
    std::vector<dealii::Tensor<1, 3>> probes;
    for (const auto &probe : summary.at("probes"))
      {
        dealii::Tensor<1, 3> u;
        for (unsigned int d = 0; d < 3; ++d)
          u[d] = probe.at("displacement").at(d);
        probes.push_back(u);
      }
    return probes;
  }
} // namespace ddfem::testing

#endif
