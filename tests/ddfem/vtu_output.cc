// VTU output of a fine run with Write VTU = every step: a VTU file per load
// step and a .pvd record that lists them in order, and two runs of the same
// input write the same bytes. deal.II puts the date and time into a VTU
// header unless its flags say otherwise, and always into a .pvd record. A
// run removes the temporary files a killed run left. A rerun from a run's
// parameters.prm gives the same results under the same scene name.
// The last step's file holds the model's 16 cells (128 points, the 8
// corners of each), the fields by name, and the displacement whose largest
// norm summary.json reports; the first step's is about a third of it (the
// load's first third, nearly linear).

#include <ddfem/app/application.h>
#include <ddfem/base/files.h>
#include <zlib.h>

#include <algorithm>
#include <filesystem>
#include <fstream>
#include <set>
#include <sstream>

#include "../tests.h"

namespace
{
  /// The text of the file @p file.
  std::string
  text_of(const std::string &file)
  {
    std::ifstream in(file);
    return std::string(std::istreambuf_iterator<char>(in),
                       std::istreambuf_iterator<char>());
  }

  /// The values of the DataArray named @p name in the VTU file @p file, as
  /// deal.II writes them: one zlib-compressed block of Float32, base64
  /// encoded after a base64 header of four UInt32 (the number of blocks,
  /// the block size, the last block's size, the compressed size).
  std::vector<float>
  vtu_values(const std::string &file, const std::string &name)
  {
    const std::string text = text_of(file);
    const std::size_t tag  = text.find("Name=\"" + name + "\"");
    AssertThrow(tag != std::string::npos,
                dealii::ExcMessage(file + " has no DataArray " + name));
    const std::size_t begin = text.find('>', tag) + 1;
    std::string       data =
      text.substr(begin, text.find("</DataArray>", begin) - begin);
    data.erase(std::remove_if(data.begin(),
                              data.end(),
                              [](const char c) { return std::isspace(c); }),
               data.end());
    const std::vector<unsigned char> header =
      dealii::Utilities::decode_base64(data.substr(0, 24));
    std::uint32_t sizes[4];
    std::memcpy(sizes, header.data(), sizeof(sizes));
    AssertThrow(sizes[0] == 1 && sizes[3] > 0,
                dealii::ExcMessage(file + ": not one compressed block"));
    const std::vector<unsigned char> compressed =
      dealii::Utilities::decode_base64(data.substr(24));
    std::vector<float> values(sizes[1] / sizeof(float));
    uLongf             size = sizes[1];
    AssertThrow(uncompress(reinterpret_cast<Bytef *>(values.data()),
                           &size,
                           compressed.data(),
                           sizes[3]) == Z_OK &&
                  size == sizes[1],
                dealii::ExcMessage(file + ": " + name + " does not inflate"));
    return values;
  }

  /// The largest norm of the 3-vectors in @p values.
  double
  largest_norm(const std::vector<float> &values)
  {
    double largest = 0;
    for (std::size_t i = 0; i + 2 < values.size(); i += 3)
      largest = std::max(largest,
                         std::sqrt(double(values[i]) * values[i] +
                                   double(values[i + 1]) * values[i + 1] +
                                   double(values[i + 2]) * values[i + 2]));
    return largest;
  }
} // namespace

int
main(int argc, char **argv)
{
  dealii::Utilities::MPI::MPI_InitFinalize mpi(argc, argv, 1);
  using namespace ddfem;

  for (const std::string run : {"first", "second"})
    {
      std::filesystem::remove_all(run);
      // The second run finds the temporary files of a run killed while
      // it wrote its results, and removes them.
      if (run == "second")
        {
          std::filesystem::create_directory(run);
          for (const std::string file :
               {"solution-0002.vtu", "solution-0009.vtu", "summary.json"})
            std::ofstream(ResultFile::partial_name(run + "/" + file)) << "half";
        }
      std::ofstream(run + ".prm")
        << testing::cantilever("2, 4, 2", "0; 0; -100")
        << "subsection Nonlinear solver\n  set Load steps = 3\nend\n"
           "subsection Output\n  set Output directory = "
        << run
        << "\n  set Screen timings = false\n"
           "  set Write VTU = every step\nend\n";
      std::ostringstream out, err;
      std::cout << run << " run: exit code "
                << app::run({run + ".prm"}, out, err) << std::endl;
    }

  std::set<std::string> files;
  for (const std::string run : {"first", "second"})
    {
      files = testing::file_names(run);
      std::cout << run << " run's files:";
      for (const std::string &file : files)
        std::cout << ' ' << file;
      std::cout << std::endl;
    }

  for (const std::string &file : files)
    {
      const std::string extension = file.substr(file.size() - 4);
      if (extension != ".vtu" && extension != ".pvd")
        continue;
      const std::string first = text_of("first/" + file);
      std::cout << file << ": the same bytes in both runs: " << std::boolalpha
                << (first == text_of("second/" + file)) << ", a date in it: "
                << (first.find("generated by the deal.II library on") !=
                    std::string::npos)
                << std::endl;
    }

  // A rerun from the parameters.prm a run wrote gives the same results,
  // and keeps the scene's name, which came from the first run's file name.
  {
    std::filesystem::remove_all("rerun");
    std::ostringstream out, err;
    std::cout << "rerun from first/parameters.prm: exit code "
              << app::run({"first/parameters.prm",
                           "--set",
                           "Output/Output directory=rerun"},
                          out,
                          err)
              << std::endl;
    for (const std::string run : {"first", "rerun"})
      std::cout << "  " << run << "'s scene name: "
                << nlohmann::json::parse(text_of(run + "/summary.json"))
                     .at("scene")
                     .get<std::string>()
                << std::endl;
    std::cout << "  the same VTU bytes: " << std::boolalpha
              << (text_of("first/solution-0003.vtu") ==
                  text_of("rerun/solution-0003.vtu"))
              << std::endl;
  }

  {
    // What the last step's file holds.
    const std::string last  = text_of("first/solution-0003.vtu");
    const std::size_t piece = last.find("<Piece");
    std::cout << "solution-0003.vtu: "
              << last.substr(piece, last.find('>', piece) - piece) << ">"
              << std::endl
              << "  point data:";
    for (std::size_t at = last.find("<PointData"), name;
         (name = last.find("Name=\"", at)) != std::string::npos;
         at = name + 6)
      std::cout << ' '
                << last.substr(name + 6, last.find('"', name + 6) - name - 6);
    std::cout << std::endl;
    const std::vector<float> u3 =
      vtu_values("first/solution-0003.vtu", "displacement");
    const std::vector<float> ids =
      vtu_values("first/solution-0003.vtu", "material_id");
    const double reported = nlohmann::json::parse(text_of("first/summary.json"))
                              .at("max_displacement")
                              .get<double>();
    std::cout << "  " << u3.size() / 3 << " displacements, largest norm "
              << largest_norm(u3) << " m, summary.json's max |u| within "
              << "Float32's precision: " << std::boolalpha
              << (std::abs(largest_norm(u3) - reported) <= 1e-6 * reported)
              << "; material ids all 1: "
              << (ids.size() == 128 &&
                  std::all_of(ids.begin(),
                              ids.end(),
                              [](const float id) { return id == 1; }))
              << std::endl;
    std::cout << "  step 1's largest displacement over step 3's: "
              << largest_norm(
                   vtu_values("first/solution-0001.vtu", "displacement")) /
                   largest_norm(u3)
              << std::endl;
  }

  std::istringstream record(text_of("first/solution.pvd"));
  for (std::string line; std::getline(record, line);)
    if (line.find("DataSet") != std::string::npos)
      std::cout << line << std::endl;
}
