// RigidPartConditions against the kinematics of hinged parts: a part held
// at two points is free to turn about the line through them; two such
// parts joined along a third line form a three-hinged arch, rigid unless
// the three hinge lines lie in one plane (then it has one infinitesimal
// mechanism); two parts joined along one line and held by nothing move as
// one rigid body plus the hinge's rotation (7 motions). Every free motion is checked
// to satisfy the conditions (its mismatch is printed).

#include <ddfem/solver/supports.h>

#include <optional>

#include "../tests.h"

using namespace ddfem;
using namespace dealii;

namespace
{
  /// A hinge line along z: the points (x, y, 0) and (x, y, 1).
  std::vector<Point<3>>
  hinge(const double x, const double y)
  {
    return {Point<3>(x, y, 0), Point<3>(x, y, 1)};
  }

  /// The largest mismatch of the free motions @p motions at the joined
  /// points @p joint between parts 0 and 1 (0 where nothing is joined).
  double
  joint_mismatch(const FullMatrix<double>    &motions,
                 const std::vector<Point<3>> &joint,
                 const Point<3>              &center)
  {
    double largest = 0;
    for (unsigned int r = 0; r < motions.n(); ++r)
      for (const Point<3> &x : joint)
        for (unsigned int d = 0; d < 3; ++d)
          {
            const auto modes      = solver::rigid_body_modes(x - center, d);
            double     difference = 0;
            for (unsigned int m = 0; m < 6; ++m)
              difference += modes[m] * (motions(m, r) - motions(6 + m, r));
            largest = std::max(largest, std::abs(difference));
          }
    return largest;
  }

  /// Parts 0 and 1 held along the lines at @p a and @p b (if given) and
  /// joined along the line at @p c: the number of free motions.
  void
  report(const std::string             &name,
         const std::optional<Point<2>> &a,
         const std::optional<Point<2>> &b,
         const Point<2>                &c)
  {
    const Point<3>              center(1, 0.5, 0.5);
    solver::RigidPartConditions conditions(2, center, 1.);
    for (unsigned int part = 0; part < 2; ++part)
      if (const auto &at = (part == 0 ? a : b); at)
        for (const Point<3> &x : hinge((*at)[0], (*at)[1]))
          for (unsigned int d = 0; d < 3; ++d)
            conditions.hold(x, d, part);
    const std::vector<Point<3>> joint = hinge(c[0], c[1]);
    for (const Point<3> &x : joint)
      for (unsigned int d = 0; d < 3; ++d)
        conditions.join(x, d, 0, 1);
    const FullMatrix<double> motions = conditions.free_motions();
    std::cout << name << ": " << motions.n() << " free motion(s), mismatch "
              << (joint_mismatch(motions, joint, center) < 1e-12 ?
                    "below 1e-12" :
                    "ABOVE 1e-12")
              << std::endl;
  }
} // namespace

int
main()
{
  // One part held along one line: the rotation about it.
  {
    solver::RigidPartConditions conditions(1, Point<3>(0, 0, 0.5), 1.);
    for (const Point<3> &x : hinge(0, 0))
      for (unsigned int d = 0; d < 3; ++d)
        conditions.hold(x, d, 0);
    const FullMatrix<double> motion = conditions.free_motions();
    std::cout << "one part held along a line: " << motion.n()
              << " free motion(s)";
    if (motion.n() == 1)
      std::cout << ", rotation about z " << std::abs(motion(5, 0))
                << ", other components "
                << (std::abs(motion(0, 0)) + std::abs(motion(1, 0)) +
                          std::abs(motion(2, 0)) + std::abs(motion(3, 0)) +
                          std::abs(motion(4, 0)) <
                        1e-12 ?
                      "below 1e-12" :
                      "ABOVE 1e-12");
    std::cout << std::endl;
  }
  report("arch, joint off the line of its supports",
         Point<2>(0, 0),
         Point<2>(2, 0),
         Point<2>(1, 1));
  report("arch, joint on the line of its supports",
         Point<2>(0, 0),
         Point<2>(2, 0),
         Point<2>(1, 0));
  report("two parts joined along a line, held nowhere",
         std::nullopt,
         std::nullopt,
         Point<2>(1, 0));
}
