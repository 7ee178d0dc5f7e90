// The load factors of a load-stepped solve (solver::LoadSteps) along a
// scripted sequence of increments that succeed or fail: 10 nominal steps;
// the increment to 0.4 fails and is halved twice; after two successes the
// increment doubles back (0.025, 0.05, 0.1); the load factor is then off the
// nominal grid, so the last increment is shortened to reach 1 (0.95 to 1),
// and when it fails, the next try is half of it (to 0.975), not the same
// increment again. A cut below 'Minimum load step' of the nominal
// increment ends the solve. Increments shorter than the nominal one after
// a cut are marked "cut"; the last, shortened to reach 1, is not.

#include <ddfem/solver/static_solver.h>

#include <algorithm>

#include "../tests.h"

using namespace ddfem;

int
main()
{
  solver::LoadSteps steps(10, 1e-3);
  // Failures at the 4th, 5th and 15th increment tried.
  const std::vector<unsigned int> failures = {4, 5, 15};
  std::cout << "tried:";
  for (unsigned int tried = 1; !steps.done() && tried < 40; ++tried)
    {
      const double from = steps.current(), to = steps.next();
      const bool   fails =
        std::find(failures.begin(), failures.end(), tried) != failures.end();
      std::cout << " " << from << "->" << to << (steps.is_cut() ? " cut" : "")
                << (fails ? " (fails)" : "");
      AssertThrow(fails ? steps.cut() : (steps.accept(), true),
                  dealii::ExcInternalError());
    }
  std::cout << "\nreached 1: " << steps.done() << std::endl;

  // Halving from 1/10 reaches 1e-3 of it after 10 cuts (1/1024 < 1e-3 is
  // the 10th): the 10th cut returns false.
  solver::LoadSteps failing(10, 1e-3);
  unsigned int      cuts = 1;
  while (failing.cut())
    ++cuts;
  std::cout << "cuts until below the minimum step: " << cuts
            << ", increment then " << failing.next() << std::endl;
}
