// ResultFile writes a result in one piece: nothing under the result's name
// until commit(), no temporary left behind by an uncommitted or failed
// write, and errors that name the file and the parameter. remove_earlier()
// also removes the temporary file a killed run left. check_creatable()
// leaves nothing behind.

#include <deal.II/base/exceptions.h>

#include <ddfem/base/exceptions.h>
#include <ddfem/base/files.h>

#include <filesystem>
#include <fstream>
#include <iostream>
#include <string>

#include "../tests.h"

namespace
{
  /// The names in @p directory, sorted, after @p what.
  void
  print_names(const std::string &directory, const std::string &what)
  {
    std::cout << what << ":";
    for (const std::string &name : ddfem::testing::file_names(directory))
      std::cout << ' ' << name;
    std::cout << std::endl;
  }

  /// The message of the ExcMessage that @p f throws.
  template <typename F>
  void
  print_error(const std::string &what, const F &f)
  {
    try
      {
        f();
        std::cout << what << ": no error" << std::endl;
      }
    catch (const dealii::ExceptionBase &e)
      {
        std::cout << what << ": " << ddfem::message_of(e) << std::endl;
      }
  }
} // namespace

int
main()
{
  using namespace ddfem;
  const std::string dir = "results";
  std::filesystem::remove_all(dir);
  std::filesystem::create_directory(dir);

  {
    ResultFile file(dir + "/a.txt", "Output/Output directory");
    file.stream() << "written\n";
    print_names(dir, "while a.txt is written");
    file.commit();
  }
  print_names(dir, "after commit");
  std::cout << "a.txt holds: " << std::ifstream(dir + "/a.txt").rdbuf();

  // A run that fails while writing: the earlier result stays whole, and the
  // temporary goes.
  try
    {
      ResultFile file(dir + "/a.txt", "Output/Output directory");
      file.stream() << "half";
      throw std::runtime_error("a failure while writing");
    }
  catch (const std::runtime_error &)
    {}
  print_names(dir, "after a failed write");
  std::cout << "a.txt holds: " << std::ifstream(dir + "/a.txt").rdbuf();

  print_error("no directory", [&]() {
    ResultFile file(dir + "/missing/b.txt", "Output/Output directory");
  });
  std::filesystem::create_directory(dir + "/c.txt");
  print_error("a directory in the way", [&]() {
    ResultFile file(dir + "/c.txt", "Output/Output directory");
    file.stream() << "text\n";
    file.commit();
  });
  print_names(dir, "after the failed commit");

  // check_creatable() makes and removes again what create_directories()
  // would make, "a" of "a/../b" included.
  print_error("a creatable path through '..'", [&]() {
    check_creatable(dir + "/x/./a/../b", "Output/Output directory");
  });
  print_names(dir, "after the check");

  // A killed run's temporary files: remove_earlier() removes them with the
  // result, and also where the result was never written.
  std::ofstream(ResultFile::partial_name(dir + "/a.txt")) << "half";
  std::ofstream(ResultFile::partial_name(dir + "/d.txt")) << "half";
  print_names(dir, "with a killed run's temporaries");
  remove_earlier_in(dir, {"a.txt", "d.txt"}, "Output/Output directory");
  print_names(dir, "after remove_earlier");
}
