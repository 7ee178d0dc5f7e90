#ifndef ddfem_tests_dg_h
#define ddfem_tests_dg_h

// Helpers shared by the DG tests: small meshes and problem data.

#include <deal.II/grid/grid_generator.h>
#include <deal.II/grid/tria.h>

#include <ddfem/dg/parameters.h>
#include <ddfem/dg/system.h>

#include <string>

namespace ddfem::testing
{
  using namespace dealii;

  /// The unit cube as 2 x 2 x 2 cells with the first one refined once, so
  /// that the mesh has hanging faces.
  inline void
  make_cube_with_hanging_faces(Triangulation<3> &tria)
  {
    GridGenerator::subdivided_hyper_cube(tria, 2, 0, 1);
    tria.begin_active()->set_refine_flag();
    tria.execute_coarsening_and_refinement();
  }

  /// "IP FE_DGQ(1)" and the like.
  inline std::string
  describe(const dg::Parameters &p)
  {
    return std::string(
             p.flux == dg::Parameters::Flux::interior_penalty ? "IP" : "BZ") +
           " " + p.element_name() + "(" + std::to_string(p.degree) + ")";
  }
} // namespace ddfem::testing

#endif
