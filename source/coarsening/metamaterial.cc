#include <deal.II/base/symmetric_tensor.h>
#include <deal.II/fe/fe_q.h>
#include <deal.II/grid/grid_generator.h>

#include <ddfem/coarsening/metamaterial.h>
#include <ddfem/solver/cell_kernel.h>
#include <ddfem/solver/discretization.h>

#include <algorithm>
#include <limits>

namespace ddfem::coarsening
{
  double
  Metamaterial::stiffness_floor(const double fraction) const
  {
    double largest = 0, smallest = std::numeric_limits<double>::max();
    for (const material::MaterialPoint &p : points)
      if (p.mu > 0)
        {
          largest  = std::max(largest, p.mu);
          smallest = std::min(smallest, p.mu);
        }
    return std::min(fraction * largest, smallest);
  }



  Metamaterial
  transform(const Metamaterial   &m,
            const CubeSymmetries &symmetries,
            const unsigned int    g)
  {
    Assert(m.points.size() == 8, ExcInternalError());
    Metamaterial image;
    image.points.resize(8);
    for (unsigned int k = 0; k < 8; ++k)
      {
        material::MaterialPoint p = m.points[k];
        p.direction               = symmetries.matrix(g) * p.direction;
        image.points[symmetries.image(g, k)] = p;
      }
    return image;
  }



  PointTies
  symmetrize_directions(Metamaterial         &m,
                        const Combination    &combination,
                        const CubeSymmetries &symmetries)
  {
    Assert(m.points.size() == 8, ExcInternalError());
    PointTies ties;
    ties.point_class.assign(8, 8);
    ties.has_spring.assign(8, true);
    std::array<SymmetricTensor<2, 3>, 8> orientation;
    for (const unsigned int g : symmetries.stabilizer(combination))
      {
        const Metamaterial image = transform(m, symmetries, g);
        for (unsigned int k = 0; k < 8; ++k)
          {
            const Tensor<1, 3> &v = image.points[k].direction;
            orientation[k] += symmetrize(outer_product(v, v));
            // Classes are numbered by their first point.
            const unsigned int j = symmetries.image(g, k);
            ties.point_class[j]  = std::min(ties.point_class[j], k);
          }
      }
    for (unsigned int k = 0; k < 8; ++k)
      {
        const auto axes = eigenvectors(orientation[k]);
        ties.has_spring[k] =
          axes[0].first - axes[1].first > 1e-6 * axes[0].first;
        m.points[k].direction = axes[0].second;
      }
    return ties;
  }



  std::optional<unsigned int>
  split_axis(const Combination &combination)
  {
    for (unsigned int a = 0; a < 3; ++a)
      {
        const unsigned int bit   = 1u << a;
        bool               split = combination[0] != combination[bit];
        for (unsigned int k = 0; k < 8; ++k)
          split &= combination[k] == combination[k & bit];
        if (split)
          return a;
      }
    return std::nullopt;
  }



  PointTies
  laminate_springs(Metamaterial &m, const unsigned int axis)
  {
    Assert(m.points.size() == 8 && axis < 3, ExcInternalError());
    const unsigned int b = (axis + 1) % 3, c = (axis + 2) % 3;
    PointTies          ties;
    ties.has_spring.assign(8, true);
    // The softer half gets the axes, whichever side of the plane it lies
    // on, so the pattern follows the materials, not the palette's order.
    const material::MaterialPoint &below = m.points[0],
                                  &above = m.points[1u << axis];
    const bool axes_above = std::make_pair(above.mu, above.lambda) <
                            std::make_pair(below.mu, below.lambda);
    for (unsigned int k = 0; k < 8; ++k)
      {
        // Neighbours in the plane alternate between the two lines of
        // their half; the quarter turn about the normal maps each point's
        // line to the next point's.
        const bool   odd   = ((k >> b) ^ (k >> c)) & 1;
        const bool   upper = (k >> axis) & 1;
        Tensor<1, 3> v;
        if (upper != axes_above)
          {
            v[b] = 1;
            v[c] = odd ? -1 : 1;
            v /= v.norm();
          }
        else
          v[odd ? c : b] = 1;
        m.points[k].direction = v;
        ties.point_class.push_back(upper ? 1u << axis : 0);
      }
    return ties;
  }



  namespace
  {
    /// The octant (0..7) of @p x relative to @p center.
    unsigned int
    octant(const Point<3> &x, const Point<3> &center)
    {
      unsigned int o = 0;
      for (unsigned int d = 0; d < 3; ++d)
        if (x[d] > center[d])
          o |= (1u << d);
      return o;
    }
  } // namespace



  CoarseElement::CoarseElement(const unsigned int level,
                               const double       point_offset)
    : fe(FE_Q<3>(1), 3)
    , offset(point_offset)
    , quadrature(solver::coarse_quadrature(level, point_offset))
  {
    GridGenerator::hyper_cube(triangulation, 0., 1.);
    dof_handler.reinit(triangulation);
    dof_handler.distribute_dofs(fe);
    fe_values =
      std::make_unique<FEValues<3>>(fe,
                                    quadrature,
                                    update_gradients | update_JxW_values);
    fe_values->reinit(dof_handler.begin_active());

    const Point<3> center(0.5, 0.5, 0.5);
    for (unsigned int q = 0; q < quadrature.size(); ++q)
      {
        const Point<3>    &x     = quadrature.point(q);
        const unsigned int child = octant(x, center);
        Point<3>           child_center;
        for (unsigned int d = 0; d < 3; ++d)
          child_center[d] = (child & (1u << d)) ? 0.75 : 0.25;
        point_child.push_back(child);
        point_subindex.push_back(level == 1 ? 0 : octant(x, child_center));
      }
  }



  Vector<double>
  CoarseElement::local_vector(const CornerDisplacements &u) const
  {
    Vector<double> local(fe.n_dofs_per_cell());
    for (unsigned int v = 0; v < 8; ++v)
      for (unsigned int c = 0; c < 3; ++c)
        local(fe.component_to_system_index(c, v)) = u[v][c];
    return local;
  }



  void
  CoarseElement::deformation_gradients(const CornerDisplacements &u,
                                       std::vector<Tensor<2, 3>> &F) const
  {
    solver::deformation_gradients(*fe_values, local_vector(u), F);
  }



  bool
  CoarseElement::energy(const CornerDisplacements &u,
                        const Metamaterial        &m,
                        double                    &energy) const
  {
    Assert(m.points.size() == n_points(), ExcInternalError());
    solver::CellContribution result;
    const bool               admissible =
      solver::integrate_cell(*fe_values,
                             local_vector(u),
                             m.points.data(),
                             material::KernelOutput::energy,
                             result);
    energy = result.energy;
    return admissible;
  }



  bool
  CoarseElement::energy_terms(const CornerDisplacements          &u,
                              const Metamaterial                 &m,
                              std::vector<std::array<double, 3>> &terms) const
  {
    Assert(m.points.size() == n_points(), ExcInternalError());
    std::vector<Tensor<2, 3>> F;
    deformation_gradients(u, F);
    terms.resize(n_points());
    material::KernelResult k;
    for (unsigned int q = 0; q < n_points(); ++q)
      {
        // The energy density is linear in (mu, lambda, C): evaluate the
        // kernel with one unit parameter at a time.
        std::array<material::MaterialPoint, 3> unit;
        unit[0].mu         = 1;
        unit[1].lambda     = 1;
        unit[2].anisotropy = 1;
        for (unsigned int t = 0; t < 3; ++t)
          {
            unit[t].direction = m.points[q].direction;
            if (!material::evaluate(
                  F[q], unit[t], material::KernelOutput::energy, k))
              return false;
            terms[q][t] = k.energy * fe_values->JxW(q);
          }
      }
    return true;
  }
} // namespace ddfem::coarsening
