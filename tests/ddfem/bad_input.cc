// Bad input: every case must give a clear message naming the parameter or
// file, exit code 1, and leave no output directory behind, nor a database,
// journal or lock file of the cases that name one out_<name>.h5 (for
// output_directory_under_a_file: no directory can be made at all).

#include <ddfem/app/application.h>
#include <nlohmann/json.hpp>
#include <sys/resource.h>
#include <sys/stat.h>

#include <csignal>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <iterator>

#include "../tests.h"

using namespace ddfem;

namespace
{
  const std::string cantilever = testing::cantilever("2, 4, 2", "0; 0; -100");

  /// The cantilever with its voxels read from @p file.
  std::string
  from_voxel_file(const std::string &file)
  {
    return cantilever +
           "subsection Layout\n  set Type = voxel file\n  subsection Voxel "
           "file\n    set File name = " +
           file + "\n  end\nend\n";
  }

  /// The cantilever voxelized from the surface mesh @p file, with the
  /// further settings @p extra of subsection Surface mesh.
  std::string
  from_surface_mesh(const std::string &file, const std::string &extra = "")
  {
    return cantilever +
           "subsection Layout\n  set Type = surface mesh\n  subsection "
           "Surface mesh\n    set File name = " +
           file + "\n" + extra + "  end\nend\n";
  }

  /// Whether @p file is what case @p name writes: out_<name> or
  /// out_<name>.<something>.
  bool
  is_output_of(const std::string &name, const std::string &file)
  {
    return file == "out_" + name || file.rfind("out_" + name + ".", 0) == 0;
  }

  /// Runs ddfem with @p arguments as case @p name and reports; of the error
  /// message only its first sentence if @p first_sentence (the rest may
  /// depend on the machine). Removes what a run of this case left before
  /// (test directories persist between runs, and that must not count as
  /// written by this one), unless @p keep_earlier (the case puts an earlier
  /// run's files in place itself).
  void
  report_run(const std::string              &name,
             const std::vector<std::string> &arguments,
             const bool                      first_sentence = false,
             const bool                      keep_earlier   = false)
  {
    if (!keep_earlier)
      for (const auto &f : std::filesystem::directory_iterator("."))
        if (is_output_of(name, f.path().filename().string()))
          std::filesystem::remove_all(f.path());
    std::ostringstream out, err;
    const int          code = app::run(arguments, out, err);
    bool               any  = false;
    for (const auto &f : std::filesystem::directory_iterator("."))
      any = any || is_output_of(name, f.path().filename().string());
    std::string message =
      first_sentence ? err.str().substr(0, err.str().find(". ") + 1) + "\n" :
                       err.str();
    // Paths under the test's directory, the same on every machine.
    const std::string here = std::filesystem::current_path().string();
    for (std::size_t at; (at = message.find(here)) != std::string::npos;)
      message.replace(at, here.size(), "<test directory>");
    std::cout << "* " << name << ": exit code " << code
              << ", output written: " << std::boolalpha << any << "\n  "
              << message << std::endl;
  }

  /// report_run() of @p prm_text (plus @p extra arguments) with its output
  /// in out_<name>.
  void
  run_case(const std::string              &name,
           const std::string              &prm_text,
           const std::vector<std::string> &extra          = {},
           const bool                      first_sentence = false,
           const bool                      keep_earlier   = false)
  {
    const std::string file = name + ".prm";
    std::ofstream(file) << prm_text
                        << "\nsubsection Output\n  set Output directory = out_"
                        << name << "\n  set Screen timings = false\nend\n";
    std::vector<std::string> arguments = {file};
    arguments.insert(arguments.end(), extra.begin(), extra.end());
    report_run(name, arguments, first_sentence, keep_earlier);
  }

  /// Writes @p prm_text to @p file, with results to @p directory, no
  /// timings and 'Write VTU' = @p vtu.
  void
  write_prm(const std::string &file,
            const std::string &prm_text,
            const std::string &directory,
            const std::string &vtu)
  {
    std::ofstream(file) << prm_text
                        << "\nsubsection Output\n  set Output directory = "
                        << directory
                        << "\n  set Screen timings = false\n  set Write VTU = "
                        << vtu << "\nend\n";
  }

  /// The files in @p directory, sorted, each after a space (" nothing"
  /// if it is empty).
  std::string
  listing(const std::string &directory)
  {
    std::string list;
    for (const std::string &f : testing::file_names(directory))
      list += " " + f;
    return list.empty() ? std::string(" nothing") : list;
  }

  /**
   * Runs ddfem on @p prm_text (plus @p extra arguments) with a directory
   * named @p blocked in the way of a result file (none if empty) and a
   * regular file named @p earlier (none if empty) in an existing output
   * directory, and lists what that directory holds after the run.
   */
  void
  run_in_existing_directory(const std::string              &name,
                            const std::string              &blocked,
                            const std::string              &prm_text,
                            const std::vector<std::string> &extra,
                            const std::string              &earlier = "")
  {
    const std::string directory = "out_" + name;
    std::filesystem::create_directories(directory + "/" + blocked);
    if (!earlier.empty())
      std::ofstream(directory + "/" + earlier);
    write_prm(name + ".prm", prm_text, directory, "none");
    std::vector<std::string> arguments = {name + ".prm"};
    arguments.insert(arguments.end(), extra.begin(), extra.end());
    std::ostringstream out, err;
    const int          code = app::run(arguments, out, err);
    std::cout << "* " << name << ": exit code " << code << ", " << directory
              << " holds:" << listing(directory) << "\n  " << err.str()
              << std::endl;
    std::filesystem::remove_all(directory);
  }

  /**
   * Runs ddfem with @p arguments where no file may grow past 10000 bytes;
   * returns its exit code, its errors in @p err.
   */
  int
  run_with_small_files(const std::vector<std::string> &arguments,
                       std::ostream                   &err)
  {
    std::ostringstream out;
    rlimit             old_limit;
    getrlimit(RLIMIT_FSIZE, &old_limit);
    rlimit limit   = old_limit;
    limit.rlim_cur = 10000;
    // A write past the limit fails (EFBIG) instead of ending the process.
    const auto old_handler = std::signal(SIGXFSZ, SIG_IGN);
    setrlimit(RLIMIT_FSIZE, &limit);
    const int code = app::run(arguments, out, err);
    setrlimit(RLIMIT_FSIZE, &old_limit);
    std::signal(SIGXFSZ, old_handler);
    return code;
  }

  /**
   * Runs ddfem on @p prm_text (plus @p extra arguments, VTU files of every
   * load step) with files limited to 10000 bytes, more than parameters.prm
   * needs and less than a VTU file of a scene of 4 x 12 x 4 voxels, so that
   * the first VTU file fails to be written once the run has begun to write
   * results, and reports whether anything is left of them.
   */
  void
  run_with_small_files(const std::string              &name,
                       const std::string              &prm_text,
                       const std::vector<std::string> &extra)
  {
    const std::string directory = "out_" + name;
    write_prm(name + ".prm", prm_text, directory, "every step");
    std::vector<std::string> arguments = {name + ".prm"};
    arguments.insert(arguments.end(), extra.begin(), extra.end());
    std::ostringstream err;
    const int          code = run_with_small_files(arguments, err);
    std::cout << "* " << name << ": exit code " << code << ", " << directory
              << " exists: " << std::boolalpha
              << std::filesystem::exists(directory) << "\n  " << err.str()
              << std::endl;
  }
} // namespace

int
main(int argc, char **argv)
{
  dealii::Utilities::MPI::MPI_InitFinalize mpi(argc, argv, 1);

  run_case("unknown_parameter",
           cantilever +
             "subsection Geometry\n  set Grid sise = 3, 3, 3\nend\n");
  // A condition beyond the last declared one: the message says how many
  // there are, in a file and with --set.
  run_case("condition_9",
           cantilever + "subsection Boundary conditions\n  subsection "
                        "Condition 9\n    set Type = fixed\n  end\nend\n");
  run_case("condition_9_set",
           cantilever,
           {"--set", "Boundary conditions/Condition 9/Type=fixed"});
  // A subsection missing inside a declared condition: no word on how many
  // conditions there are.
  run_case("condition_3_subsection",
           cantilever + "subsection Boundary conditions\n  subsection "
                        "Condition 3\n    subsection Foo\n    end\n  "
                        "end\nend\n");
  run_case(
    "negative_E",
    cantilever +
      "subsection Materials\n  set Palette = E=1e5 nu=0.3; E=-2 nu=0.3\nend\n");
  run_case("nu_too_large",
           cantilever +
             "subsection Materials\n  set Palette = E=1e5 nu=0.5\nend\n");
  run_case("nu_too_small",
           cantilever +
             "subsection Materials\n  set Palette = E=1e5 nu=-1.2\nend\n");
  // The Neo-Hookean energy has no lower bound for lambda < 0; DG takes it.
  run_case("negative_lambda_fine",
           cantilever +
             "subsection Materials\n  set Palette = E=1e5 nu=-0.2\nend\n");
  run_case("negative_lambda_dg",
           cantilever +
             "subsection Materials\n  set Palette = E=1e5 nu=-0.2\nend\n",
           {"--set", "Method=dg"});
  run_case("negative_lambda_database",
           cantilever +
             "subsection Materials\n  set Palette = E=1e5 nu=-0.2\nend\n",
           {"--set",
            "Run type=database",
            "--set",
            "Database/File=out_negative_lambda_database.h5"});
  run_case("negative_lambda_compare",
           cantilever +
             "subsection Materials\n  set Palette = E=1e5 nu=-0.2\nend\n",
           {"--set", "Run type=compare"});
  // E is small; lambda is not.
  run_case("nu_near_half",
           cantilever + "subsection Materials\n  set Palette = "
                        "E=1e5 nu=0.4999999999999999\nend\n");
  run_case("missing_voxel_file", from_voxel_file("no_such_file.txt"));
  run_case("missing_mesh_file", from_surface_mesh("no_such_mesh.stl"));
  // Found before the mesh is read, and not blamed on the mesh.
  run_case("surface_mesh_void_inside",
           from_surface_mesh("no_such_mesh.stl"),
           {"--set", "Layout/Material=0"});

  std::ofstream("wrong_size.txt") << "3 4 2\n"
                                  << std::string(24 * 2, ' ') << "\n";
  std::ofstream("wrong_size.txt", std::ios::app)
    << "1 1 1 1 1 1 1 1 1 1 1 1 1 1 1 1 1 1 1 1 1 1 1 1\n";
  run_case("inconsistent_grid", from_voxel_file("wrong_size.txt"));
  // A file that includes itself (ParameterHandler would recurse until the
  // stack overflows), and two that include each other (an included file
  // is read as PRM text whatever its name).
  run_case("include_cycle", "include include_cycle.prm\n" + cantilever);
  // ParameterHandler also takes a tab after "include", and joins a line
  // that ends in a backslash to the next.
  run_case("include_cycle_tab",
           "include\tinclude_cycle_tab.prm\n" + cantilever);
  run_case("include_directory", "include .\n" + cantilever);
  run_case("include_cycle_continued",
           "include include_cycle_\\\n  continued.prm\n" + cantilever);
  // A JSON parameter file can hold values that parameters.prm cannot
  // (a '#' would start a comment there, so a rerun read "Run").
  {
    std::ofstream("hash_in_json.json")
      << "{\"Scene name\": \"Run #3\", \"Output\": {\"Output directory\": "
         "\"out_hash_in_json\"}}\n";
    report_run("hash_in_json", {"hash_in_json.json"});
    // Nor white space at a value's ends, which ParameterHandler trims from
    // a parameter file's values (a rerun wrote into another directory).
    std::ofstream("padded_json.json")
      << "{\"Output\": {\"Output directory\": \"out_padded_json \"}}\n";
    report_run("padded_json", {"padded_json.json"});
  }
  // A scene named by its file, whose name parameters.prm cannot hold: a
  // rerun from it took the name "parameters".
  {
    std::ofstream("hash#name.prm")
      << cantilever
      << "subsection Output\n  set Output "
         "directory = out_hash_in_file_name\nend\n";
    report_run("hash_in_file_name", {"hash#name.prm"});
  }
  // ParameterHandler also reads a last line that ends in a backslash.
  {
    std::ofstream("include_cycle_last_line.prm")
      << cantilever
      << "subsection Output\n  set Output directory = "
         "out_include_cycle_last_line\nend\ninclude "
         "include_cycle_last_line.prm\\";
    report_run("include_cycle_last_line", {"include_cycle_last_line.prm"});
  }
  std::ofstream("include_other.inc") << "include include_each_other.prm\n";
  run_case("include_each_other", "include include_other.inc\n" + cantilever);
  // What a text file may hold, and runs: CRLF line ends, a form feed,
  // UTF-8, and a control character in a comment (ParameterHandler drops
  // comments, and a DOS file may end in ^Z).
  {
    std::string text = "# Ma\xc3\x9f"
                       "e in m \x1a\n\f\n" +
                       cantilever +
                       "subsection Output\n  set Output directory = "
                       "out_text_file_that_runs\nend\n";
    for (std::size_t at = 0; (at = text.find('\n', at)) != std::string::npos;
         at += 2)
      text.insert(at, "\r");
    std::ofstream("text_file_that_runs.prm", std::ios::binary) << text;
    report_run("text_file_that_runs", {"text_file_that_runs.prm"});
  }
  // A binary file as the parameter file, or included by it: ParameterHandler
  // echoed its bytes in the message.
  {
    const std::string bytes("\x7f"
                            "ELF\x02\x01\x01\0\0\n",
                            10);
    std::ofstream("binary.prm", std::ios::binary) << bytes;
    report_run("binary_parameter_file", {"binary.prm"});
    std::ofstream("binary.inc", std::ios::binary) << "# a comment\n" << bytes;
    run_case("binary_include", "include binary.inc\n" + cantilever);
  }
  // A carriage return, form feed or vertical tab inside a line, which
  // ParameterHandler kept in the value (a printed value overwrote the
  // screen's line; the scene-name check blamed the file's name), and a C1
  // control in UTF-8 (U+009B, which a terminal may take as ESC '['), in a value
  // and in an override.
  run_case("carriage_return_in_value", cantilever + "set Scene name = a\rb\n");
  run_case("form_feed_in_value", cantilever + "set Scene name = a\fb\n");
  run_case("vertical_tab_in_override",
           cantilever,
           {"--set", "Scene name=a\vb"});
  run_case("c1_control_in_value",
           cantilever + "set Scene name = a\xc2\x9b"
                        "b\n");
  run_case("c1_control_in_override",
           cantilever,
           {"--set",
            "Scene name=a\xc2\x9b"
            "b"});
  // 1e308 degrees overflowed to an infinite angle in radians, whose NaN
  // boundary values the Newton solver took as reached.
  run_case("rotation_angle",
           cantilever,
           {"--set",
            "Boundary conditions/Condition 2/Type=rotation",
            "--set",
            "Boundary conditions/Condition 2/Angle=1e308"});
  // Layouts that would paint nothing: a box given in voxel indices instead
  // of meters, layers thinner than a voxel, and a skin thinner than half a
  // voxel.
  run_case("shape_outside_grid",
           cantilever +
             "subsection Layout\n  set Shapes = box 1 1 1 2 2 2 : 2\n"
             "end\n");
  run_case("layers_thinner_than_a_voxel",
           cantilever + "subsection Layout\n  set Type = layers\n"
                        "  subsection Layers\n    set Materials = 1, 2\n"
                        "    set Thickness = 0.005\n  end\nend\n");
  // Layers of half a voxel whose three materials each land on a voxel
  // center (ran before as one-voxel layers in another order), and a skin
  // or fibers that cover every voxel, leaving none of Layout/Material.
  run_case("layers_thinner_than_a_voxel_every_material_landing",
           cantilever + "subsection Layout\n  set Type = layers\n"
                        "  subsection Layers\n    set Materials = 1, 2, 3\n"
                        "    set Thickness = 0.005\n  end\nend\n");
  run_case("skin_covering_every_voxel",
           cantilever + "subsection Layout\n  set Type = skin\n"
                        "  subsection Skin\n    set Thickness = 0.01\n  end\n"
                        "end\n");
  run_case("fibers_covering_every_voxel",
           cantilever + "subsection Layout\n  set Type = fibers\n"
                        "  subsection Fibers\n    set Fiber radius = 1\n"
                        "  end\nend\n");
  run_case("skin_thinner_than_half_a_voxel",
           cantilever + "subsection Layout\n  set Type = skin\n"
                        "  subsection Skin\n    set Thickness = 0.004\n  end\n"
                        "end\n");
  run_case("material_not_in_palette",
           cantilever + "subsection Layout\n  set Material = 4\nend\n");
  run_case("skin_material_not_in_palette",
           cantilever + "subsection Layout\n  set Type = skin\n"
                        "  subsection Skin\n    set Skin material = 4\n"
                        "  end\nend\n");
  run_case("fiber_material_not_in_palette",
           cantilever + "subsection Layout\n  set Type = fibers\n"
                        "  subsection Fibers\n    set Fiber material = 4\n"
                        "  end\nend\n");
  run_case("bad_expression",
           cantilever +
             "subsection Loads\n  set Body force = 0; 0; -9.81*rho\nend\n");
  run_case("bad_region",
           cantilever +
             "subsection Boundary conditions\n  subsection Condition 3\n"
             "    set Type = fixed\n    set Region = top\n  end\nend\n");
  run_case("bad_override",
           cantilever,
           {"--set", "Nonlinear solver/Load steps=-3"});
  run_case("unknown_override", cantilever, {"--set", "Solver/Load steps=3"});
  run_case("line_break_in_override", cantilever, {"--set", "Scene name=a\nb"});
  // Nor could a '#' or a final '\\' be read back from parameters.prm.
  run_case("hash_in_override", cantilever, {"--set", "Scene name=Run #3"});
  run_case("backslash_in_override", cantilever, {"--set", "Scene name=a\\"});
  // ... nor a control character, which the check of parameter files
  // refuses.
  // A tab, which a parameter file reads as a space, and a control
  // character before the '=' of an argument without a value: no message
  // echoes it.
  run_case("tab_in_override", cantilever, {"--set", "Scene name=a\tb"});
  run_case("control_character_in_override_name",
           cantilever,
           {"--set",
            "Scene\x1b"
            "name"});
  run_case("control_character_in_override",
           cantilever,
           {"--set",
            "Scene name=a\x01"
            "b"});
  // JSON results need UTF-8 text: a Latin-1 scene name, given or taken
  // from the parameter file's name, is an error before anything runs.
  run_case("latin1_scene_name",
           cantilever,
           {"--set",
            "Scene name=Br\xfc"
            "cke"});
  run_case("latin1_file_name_\xfc", cantilever);
  run_case("zero_linear_tolerance",
           cantilever,
           {"--set", "Linear solver/Tolerance=0"});
  // A reduction of 1 asked nothing of the solve that lifts a load step to
  // its boundary values.
  run_case("linear_tolerance_one",
           cantilever,
           {"--set", "Linear solver/Tolerance=1"});
  run_case("unknown_override_entry",
           cantilever,
           {"--set", "Nonlinear solver/Load stepz=3"});
  run_case("unknown_override_top_level", cantilever, {"--set", "Methd=fine"});
  run_case(
    "coarse_point_offset",
    cantilever,
    {"--set", "Method=naive", "--set", "Discretization/Coarse point offset=1"});
  run_case(
    "held_out_every",
    cantilever,
    {"--set", "Method=ddfem", "--set", "Database/Fitting/Held-out every=1"});
  run_case("spring_regularization",
           cantilever,
           {"--set",
            "Method=ddfem",
            "--set",
            "Database/Fitting/Spring regularization=-1"});
  // A weight of 1e305 overflowed the least-squares solver: every fit
  // collapsed, was saved, and the coarse solve failed.
  run_case("huge_regularization",
           cantilever,
           {"--set",
            "Method=ddfem",
            "--set",
            "Database/Fitting/Regularization=1e305"});
  run_case("held_out_beyond_patterns",
           cantilever,
           {"--set",
            "Method=ddfem",
            "--set",
            "Database/Sampling/Patterns=10",
            "--set",
            "Database/Fitting/Held-out every=11"});
  // Half of 8 patterns embedded: 4 of each kind, none of them the 5th.
  run_case("held_out_beyond_patterns_of_a_kind",
           cantilever,
           {"--set",
            "Method=ddfem",
            "--set",
            "Database/Sampling/Patterns=8",
            "--set",
            "Database/Sampling/Embedded fraction=0.5",
            "--set",
            "Database/Fitting/Held-out every=5"});
  run_case("spring_regularization_word",
           cantilever,
           {"--set",
            "Method=ddfem",
            "--set",
            "Database/Fitting/Spring regularization=Same"});
  // Refused before any fit, not by the first level-2 fit after all of
  // level 1; a run that fits no level-2 entry (naive) takes it.
  run_case(
    "level2_regularization_zero_naive",
    cantilever,
    {"--set", "Method=naive", "--set", "Database/Level 2/Regularization=0"});
  run_case("level2_regularization_zero_level1",
           cantilever,
           {"--set",
            "Method=ddfem",
            "--set",
            "Database/File=out_level2_regularization_zero_level1.h5",
            "--set",
            "Database/Level 2/Regularization=0"});
  run_case("level2_regularization_zero",
           cantilever,
           {"--set",
            "Method=ddfem",
            "--set",
            "Coarsening levels=2",
            "--set",
            "Database/Level 2/Regularization=0"});
  // A simulation fits the blocks its scene lacks and compresses nothing.
  run_case("compression_in_simulation",
           cantilever,
           {"--set",
            "Method=ddfem",
            "--set",
            "Database/File=out_compression_in_simulation.h5",
            "--set",
            "Database/Representatives=10"});
  // 2e6 samples per block, each within its parameter's range.
  run_case("samples_per_block_beyond_range",
           cantilever,
           {"--set",
            "Method=ddfem",
            "--set",
            "Database/File=out_samples_per_block_beyond_range.h5",
            "--set",
            "Database/Sampling/Patterns=20000",
            "--set",
            "Database/Sampling/Magnitudes=100"});
  // The database's settings concern ddfem alone: a naive run that gives
  // none runs.
  run_case("naive_without_database_file",
           cantilever,
           {"--set",
            "Method=naive",
            "--set",
            "Database/File=",
            "--set",
            "Database/Sampling/Patterns=10",
            "--set",
            "Database/Fitting/Held-out every=11"});
  run_case("negative_lambda_ddfem",
           cantilever,
           {"--set",
            "Method=ddfem",
            "--set",
            "Materials/Palette=E=1e6 nu=-0.2",
            "--set",
            "Database/File=out_negative_lambda_ddfem.h5"});

  run_case(
    "probe_outside",
    cantilever +
      "subsection Geometry\n  set Probe points = 0.01, 0.02, 0.5\nend\n");
  // The message shows the point to more digits than the default four.
  run_case("probe_just_outside",
           cantilever + "subsection Geometry\n  set Probe points = "
                        "0.02000000001, 0.04, 0.02\nend\n");
  run_case(
    "zero_radius",
    cantilever +
      "subsection Layout\n  set Shapes = sphere 0.01 0.01 0.01 0 : 2\nend\n");
  run_case("infinite_modulus",
           cantilever +
             "subsection Materials\n  set Palette = E=inf nu=0.3\nend\n");
  // strtod() reads "0x1p17" as 131072; a palette means decimal numbers.
  run_case("hexadecimal_modulus",
           cantilever +
             "subsection Materials\n  set Palette = E=0x1p17 nu=0.3\nend\n");
  run_case(
    "bad_rotation_center",
    cantilever +
      "subsection Boundary conditions\n  subsection Condition 2\n"
      "    set Type = rotation\n    set Center = 0.01, middle\n  end\nend\n");
  // A step prescribes where the nodes end: 360 degrees per step would
  // prescribe no motion at all.
  run_case("rotation_step_too_large",
           cantilever +
             "subsection Boundary conditions\n  subsection Condition 2\n"
             "    set Type = rotation\n    set Angle = -3600\n  end\nend\n");
  // At most 90 degrees per step: 1620 degrees in 17 steps are 95.3 per
  // step, and 180 degrees in 2 steps, read back from radians as a hair
  // more, are exactly 90.
  run_case("rotation_step_above_90",
           cantilever +
             "subsection Boundary conditions\n  subsection Condition 2\n"
             "    set Type = rotation\n    set Angle = 1620\n  end\nend\n"
             "subsection Nonlinear solver\n  set Load steps = 17\nend\n");
  // Linear DG solves once: a full turn in that one step prescribes none.
  run_case("rotation_in_linear_dg",
           cantilever +
             "subsection Boundary conditions\n  subsection Condition 2\n"
             "    set Type = rotation\n    set Angle = 360\n  end\nend\n",
           {"--set", "Method=dg"});
  // A centre so far away that the displacement it prescribes overflows.
  run_case("rotation_center_far_away",
           cantilever +
             "subsection Boundary conditions\n  subsection Condition 2\n"
             "    set Type = rotation\n    set Axis = 1, 1, 1\n"
             "    set Center = 1.7e308, 1.7e308, 1.7e308\n  end\nend\n");
  run_case("newton_iterations_beyond_range",
           cantilever + "subsection Nonlinear solver\n"
                        "  set Maximum Newton iterations = 2000000000\nend\n");
  run_case("rotation_step_exactly_90",
           cantilever +
             "subsection Boundary conditions\n  subsection Condition 2\n"
             "    set Type = rotation\n    set Angle = 180\n  end\nend\n"
             "subsection Nonlinear solver\n  set Load steps = 2\nend\n");
  run_case("displacement_all_free",
           cantilever +
             "subsection Boundary conditions\n  subsection Condition 2\n"
             "    set Type = displacement\n    set Value = free; free; free\n"
             "  end\nend\n");
  // Conditions 3 (y) and 4 (x and z) hold every component condition 1
  // holds, at every node it holds: condition 1 would do nothing.
  run_case("overridden_condition",
           cantilever +
             "subsection Boundary conditions\n  subsection Condition 3\n"
             "    set Type = sliding\n    set Region = y-\n  end\n"
             "  subsection Condition 4\n    set Type = displacement\n"
             "    set Region = y-\n    set Value = 0; free; 0\n  end\nend\n");
  // Not an error: condition 1 keeps the voxels' nodes at y = 0.01 to
  // itself, which the level-1 grid does not have (its nodes lie at y = 0
  // and 0.02, where conditions 3 and 4 override it). The coarse model
  // takes the fine voxels' verdict.
  const std::string kept_between_coarse_nodes =
    cantilever +
    "subsection Boundary conditions\n  subsection Condition 1\n"
    "    set Region = box 0 0 0 0.02 0.02 0.02\n  end\n"
    "  subsection Condition 3\n    set Type = fixed\n    set Region = y-\n"
    "  end\n  subsection Condition 4\n    set Type = fixed\n"
    "    set Region = box 0 0.02 0 0.02 0.02 0.02\n  end\nend\n";
  run_case("kept_between_coarse_nodes", kept_between_coarse_nodes);
  run_case("kept_between_coarse_nodes_naive",
           kept_between_coarse_nodes,
           {"--set", "Method=naive", "--set", "Database/File="});
  run_case("minimum_step_zero",
           cantilever +
             "subsection Nonlinear solver\n  set Minimum load step = 0\nend\n");
  run_case("load_misses_solid",
           cantilever +
             "subsection Boundary conditions\n  subsection Condition 2\n"
             "    set Region = box 1 1 1 2 2 2\n  end\nend\n");
  // The tip traction moved onto the clamped face, and a pressure on a
  // sliding face: each loads held components only.
  run_case("load_on_held_face",
           cantilever +
             "subsection Boundary conditions\n  subsection Condition 2\n"
             "    set Region = y-\n  end\nend\n");
  // A load on a strip of faces between two held lines: at degree 1 all
  // its nodes are held, though its faces' centers are not.
  run_case("load_between_held_lines",
           cantilever +
             "subsection Boundary conditions\n  subsection Condition 2\n"
             "    set Region = box 0 0.04 0 0.01 0.04 0.02\n  end\n"
             "  subsection Condition 3\n    set Type = fixed\n"
             "    set Region = box 0 0.04 0 0 0.04 0.02\n  end\n"
             "  subsection Condition 4\n    set Type = fixed\n"
             "    set Region = box 0.01 0.04 0 0.01 0.04 0.02\n  end\nend\n");
  // A load on the same strip, held on one line only, that is zero on the
  // free line: it is not zero at the faces' Gauss points, and the free
  // nodes' shape functions carry it there, so it moves the part.
  const std::string tapering_to_held_line =
    cantilever + "subsection Boundary conditions\n  subsection Condition 2\n"
                 "    set Region = box 0 0.04 0 0.01 0.04 0.02\n"
                 "    set Value = 0; 0; -1e7*(0.01-x)\n  end\n"
                 "  subsection Condition 3\n    set Type = fixed\n"
                 "    set Region = box 0 0.04 0 0 0.04 0.02\n  end\nend\n";
  run_case("load_tapering_to_held_line", tapering_to_held_line);
  run_case("load_tapering_to_held_line_dg",
           tapering_to_held_line,
           {"--set", "Method=dg", "--set", "DG/Dirichlet=strong"});
  // A body force on a part held at every node (the clamp's box given in
  // millimeters covers it all): it would all go into the reactions.
  run_case("body_force_on_held_part",
           cantilever +
             "subsection Boundary conditions\n  subsection Condition 1\n"
             "    set Region = box 0 0 0 20 40 20\n  end\n"
             "  subsection Condition 2\n    set Type = none\n  end\nend\n"
             "subsection Loads\n  set Body force = 0; 0; -9810\nend\n");
  run_case("pressure_on_sliding_face",
           cantilever +
             "subsection Boundary conditions\n  subsection Condition 3\n"
             "    set Type = sliding\n    set Region = x-\n  end\n"
             "  subsection Condition 4\n    set Type = pressure\n"
             "    set Region = x-\n    set Value = 1e3\n  end\nend\n");
  run_case("repeated_palette_key",
           cantilever + "subsection Materials\n  set Palette = E=1e5 nu=0.3 "
                        "nu=0.2\nend\n");
  run_case("tiny_voxel",
           cantilever +
             "subsection Geometry\n  set Voxel size = 1e-100\nend\n");
  run_case("negative_voxel",
           cantilever + "subsection Geometry\n  set Voxel size = -0.02\nend\n");
  run_case("zero_rotation_axis",
           cantilever +
             "subsection Boundary conditions\n  subsection Condition 2\n"
             "    set Type = rotation\n    set Axis = 0, 0, 0\n"
             "  end\nend\n");
  run_case("huge_modulus",
           cantilever + "subsection Materials\n  set Palette = E=1e5 nu=0.3; "
                        "E=1e308 nu=0.45\nend\n");
  run_case("zero_skin",
           cantilever + "subsection Layout\n  set Type = skin\n"
                        "  subsection Skin\n    set Thickness = 0\n"
                        "  end\nend\n");
  run_case("no_skin_faces",
           cantilever + "subsection Layout\n  set Type = skin\n"
                        "  subsection Skin\n    set Faces =\n"
                        "  end\nend\n");
  run_case("thin_layers",
           cantilever + "subsection Layout\n  set Type = layers\n"
                        "  subsection Layers\n    set Thickness = 1e-300\n"
                        "  end\nend\n");
  run_case("no_compared_levels",
           cantilever,
           {"--set", "Run type=compare", "--set", "Comparison/Levels="});
  // Expressions that are not finite where they act, found before any solve.
  run_case("infinite_traction",
           cantilever +
             "subsection Boundary conditions\n  subsection Condition 2\n"
             "    set Value = 0; 0; 1/(y-0.04)\n  end\nend\n");
  run_case("nan_body_force",
           cantilever +
             "subsection Loads\n  set Body force = 0; 0; log(x-1)\nend\n");
  // muparser syntax that is valid but a typo: a decimal comma (muparser
  // would keep the 81 of "-9,81"), an assignment meant as '=='.
  run_case("decimal_comma_in_body_force",
           cantilever +
             "subsection Loads\n  set Body force = 0; 0; -9,81*1000\nend\n");
  // Inside a function of any number of arguments, "1,5" would be two.
  run_case("decimal_comma_in_min",
           cantilever + "subsection Loads\n  set Body force = 0; 0; -min(2000, "
                        "1,5e4*y)\nend\n");
  run_case("assignment_in_traction",
           cantilever +
             "subsection Boundary conditions\n  subsection Condition 2\n"
             "    set Value = 0; 0; (y=0.32)*-100\n  end\nend\n");
  // A shape that a later one paints over entirely has no effect.
  run_case("shape_painted_over",
           cantilever + "subsection Layout\n  set Shapes = box 0 0 0 0.02 "
                        "0.02 0.02 : 2; box 0 0 0 0.02 0.04 0.02 : 1\nend\n");
  // A material id too large for an integer is named as given.
  run_case("shape_id_outside_palette",
           cantilever + "subsection Layout\n  set Shapes = box 0 0 0 0.02 "
                        "0.02 0.02 : 1e30\nend\n");
  run_case("cylinder_axis_overflows",
           cantilever + "subsection Layout\n  set Shapes = cylinder 0.01 0 "
                        "0.01 0.01 1e200 0.01 0.01 : 1\nend\n");
  // An all-void layout is named as such, not as a probe outside the solid.
  run_case("all_void_layers",
           cantilever + "subsection Layout\n  set Type = layers\n"
                        "  subsection Layers\n    set Materials = 0\n"
                        "  end\nend\n");
  // Every edit is checked before the first state is solved.
  run_case("second_edit_removes_voxels",
           cantilever + "subsection Layout\n  set Edits = box 0 0 0 1 1 1 : 2 "
                        "| box 0 0 0 0.01 0.01 0.01 : 0\nend\n");
  run_case("edit_adds_voxels",
           cantilever + "subsection Layout\n  set Shapes = box 0 0.01 0 0.01 "
                        "0.02 0.01 : 0\n  set Edits = box 0 0 0 1 1 1 : 2\n"
                        "end\n");
  run_case("dg_with_edits",
           cantilever,
           {"--set", "Method=dg", "--set", "Layout/Edits=box 0 0 0 1 1 1 : 2"});
  run_case("empty_edit",
           cantilever + "subsection Layout\n  set Edits = | \nend\n");
  // The second edit paints what the first painted.
  run_case("edit_changes_nothing",
           cantilever + "subsection Layout\n  set Edits = box 0 0 0 1 1 1 : 2 "
                        "| box 0 0 0 1 1 1 : 2\nend\n");
  // A comparison checks that every coarse model's grid coarsens before the
  // fine model is solved.
  run_case("compare_grid_not_divisible",
           cantilever,
           {"--set",
            "Run type=compare",
            "--set",
            "Geometry/Grid size=3, 4, 2",
            "--set",
            "Comparison/Methods=naive",
            "--set",
            "Comparison/Levels=1"});
  // A grid whose mesh could not fit in the memory of any machine we run
  // on (1.95e8 solid voxels, at least 8 KiB each): an error before the
  // mesh is built, not the out-of-memory killer. The message goes on with
  // this machine's memory.
  run_case("grid_exceeds_memory",
           cantilever,
           {"--set", "Geometry/Grid size=580, 580, 580"},
           true);
  // A probe in a void voxel: a coarse element spans it, but no material
  // does, so no model may report a displacement there.
  run_case("naive_probe_in_void",
           cantilever + "subsection Geometry\n  set Probe points = 0.005, "
                        "0.035, 0.005\nend\nsubsection Layout\n  set Shapes "
                        "= box 0 0.03 0 0.01 0.04 0.01 : 0\nend\n",
           {"--set", "Method=naive"});
  // A support that a coarse grid cannot hold where the fine one is held.
  run_case("naive_support_between_coarse_nodes",
           cantilever + "subsection Boundary conditions\n  subsection "
                        "Condition 1\n    set Region = box 0 0 0 0.02 0.01 "
                        "0.02\n  end\nend\n",
           {"--set", "Method=naive"});
  // Method = ddfem checks the rest of its input before it fits anything:
  // no database file is written (it would go into the output directory).
  run_case("ddfem_probe_outside",
           cantilever +
             "subsection Geometry\n  set Probe points = 0.01, 0.02, 0.5\nend\n",
           {"--set",
            "Method=ddfem",
            "--set",
            "Database/File=out_ddfem_probe_outside/db.h5"});
  run_case("zero_stiffness_floor",
           cantilever,
           {"--set",
            "Method=ddfem",
            "--set",
            "Database/Fitting/Stiffness floor=0",
            "--set",
            "Database/File=out_zero_stiffness_floor.h5"});
  // Database/File as a link in a loop of links (it was taken as it was
  // after 40 of them).
  for (const auto &[link, target] :
       {std::pair("link_loop_a.h5", "link_loop_b.h5"),
        std::pair("link_loop_b.h5", "link_loop_a.h5")})
    {
      std::filesystem::remove(link);
      std::filesystem::create_symlink(target, link);
    }
  run_case("database_link_loop",
           cantilever,
           {"--set", "Method=ddfem", "--set", "Database/File=link_loop_a.h5"});
  // ... and in a directory of its path, which reported the file system's
  // own exception without the parameter's name.
  run_case(
    "database_directory_link_loop",
    cantilever,
    {"--set", "Method=ddfem", "--set", "Database/File=link_loop_a.h5/db.h5"});
  run_case("ddfem_quadratic",
           cantilever,
           {"--set",
            "Method=ddfem",
            "--set",
            "Discretization/Polynomial degree=2",
            "--set",
            "Database/File=out_ddfem_quadratic/db.h5"});
  run_case("database_file_is_a_directory",
           cantilever,
           {"--set",
            "Method=ddfem",
            "--set",
            "Database/File=out_database_file_is_a_directory/"});
  // Database/File, or the temporary it is saved under, is not a regular
  // file: a named pipe made the read wait forever, a directory failed only
  // at the save, after the fits.
  std::filesystem::remove("named_pipe.h5");
  AssertThrow(mkfifo("named_pipe.h5", 0600) == 0,
              dealii::ExcMessage("cannot make a named pipe"));
  run_case("database_file_is_a_named_pipe",
           cantilever,
           {"--set", "Method=ddfem", "--set", "Database/File=named_pipe.h5"});
  std::filesystem::remove_all("partial_in_the_way.h5.partial");
  std::filesystem::create_directory("partial_in_the_way.h5.partial");
  run_case(
    "database_temporary_is_a_directory",
    cantilever,
    {"--set", "Method=ddfem", "--set", "Database/File=partial_in_the_way.h5"});
  // Database/File named as a result of the run (summary.json, a VTU file
  // of a model's directory in a comparison): the results would overwrite
  // it, or the next run would remove it as an earlier run's.
  run_case("database_file_is_a_result",
           cantilever,
           {"--set",
            "Method=ddfem",
            "--set",
            "Database/File=out_database_file_is_a_result/summary.json"});
  run_case("database_file_is_a_compare_result",
           cantilever,
           {"--set",
            "Run type=compare",
            "--set",
            "Comparison/Levels=1",
            "--set",
            "Database/File=out_database_file_is_a_compare_result/ddfem-L1/"
            "solution-0002.vtu"});
  // The same with the output directory named with a final separator, or
  // through a directory not yet made: the check compared "out/" with
  // "out", and the run overwrote the database.
  run_case("database_file_is_a_result_slash",
           cantilever,
           {"--set",
            "Method=ddfem",
            "--set",
            "Output/Output directory=out_database_file_is_a_result_slash/",
            "--set",
            "Database/File=out_database_file_is_a_result_slash/summary.json"});
  run_case(
    "database_file_is_a_result_dotdot",
    cantilever,
    {"--set",
     "Method=ddfem",
     "--set",
     "Output/Output directory=out_database_file_is_a_result_dotdot/new/..",
     "--set",
     "Database/File=out_database_file_is_a_result_dotdot/summary.json"});
  // The database where the output directory is to be: it was fitted, then
  // the directory could not be made.
  run_case("database_file_is_the_output_directory",
           cantilever,
           {"--set",
            "Method=ddfem",
            "--set",
            "Database/File=out_database_file_is_the_output_directory"});
  // The database where a compared model's VTU files go: it was fitted, and
  // the models solved, before the directory could not be made.
  run_case("database_file_is_a_model_directory",
           cantilever,
           {"--set",
            "Run type=compare",
            "--set",
            "Comparison/Levels=1",
            "--set",
            "Database/File=out_database_file_is_a_model_directory/ddfem-L1"});
  // A name whose last part is '.': no file (it was fitted, then failed).
  run_case("database_file_is_dot",
           cantilever,
           {"--set", "Method=ddfem", "--set", "Database/File=db_directory/."});
  run_case("newton_tolerance_one",
           cantilever,
           {"--set", "Nonlinear solver/Newton tolerance=1"});
  // A scene named by its file, whose name holds a control character that
  // the screen would take as a command, or a tab.
  for (const auto &[name, file] :
       {std::pair("scene_name_control_character", "escape_\033[31m.prm"),
        std::pair("scene_name_c1_control",
                  "csi_\xc2\x9b"
                  "31m.prm"),
        std::pair("scene_name_tab", "tab\tin_name.prm")})
    {
      std::ofstream(file) << cantilever
                          << "\nsubsection Output\n  set Output directory = "
                          << "out_" << name << "\nend\n";
      report_run(name, {file});
    }
  // A message that names such a file shows the character as "\x1b".
  {
    const std::string file = "escape_\033[31m_unknown.prm";
    std::ofstream(file) << cantilever << "\nset Unknown parameter = 1\n"
                        << "subsection Output\n  set Output directory = "
                        << "out_prm_file_name_control_character\nend\n";
    report_run("prm_file_name_control_character", {file});
  }
  // Files and directories in the way.
  std::ofstream("a_file") << "not a directory\n";
  run_case("output_directory_under_a_file",
           cantilever,
           {"--set", "Output/Output directory=a_file/out"});
  {
    std::cout << "  a_file unchanged: " << std::boolalpha
              << (std::filesystem::is_regular_file("a_file") &&
                  testing::content_of("a_file") == "not a directory\n")
              << "\n"
              << std::endl;
  }
  // A parameter file that is not a regular file: a directory gave nothing
  // to read, a named pipe (here) waited for a writer forever, and so did an
  // included one; /dev/zero was read until memory ran out.
  std::filesystem::create_directories("directory.prm");
  std::filesystem::remove("named_pipe.prm");
  AssertThrow(mkfifo("named_pipe.prm", 0600) == 0,
              dealii::ExcMessage("cannot make a named pipe"));
  for (const auto &[name, file] :
       {std::pair("parameter_file_is_a_directory", "directory.prm"),
        std::pair("parameter_file_is_a_named_pipe", "named_pipe.prm")})
    {
      std::ostringstream out, err;
      const int          code = app::run({file}, out, err);
      std::cout << "* " << name << ": exit code " << code << "\n  " << err.str()
                << std::endl;
    }
  run_case("include_named_pipe", "include named_pipe.prm\n" + cantilever);
  std::filesystem::remove("device.stl");
  std::filesystem::create_symlink("/dev/zero", "device.stl");
  run_case("mesh_file_is_a_device", from_surface_mesh("device.stl"));
  std::filesystem::remove("named_pipe.txt");
  AssertThrow(mkfifo("named_pipe.txt", 0600) == 0,
              dealii::ExcMessage("cannot make a named pipe"));
  run_case("voxel_file_is_a_named_pipe", from_voxel_file("named_pipe.txt"));
  // Command lines: an option where the parameter file belongs, --set
  // without its value, and --help with an argument.
  std::ofstream("command_line.prm") << cantilever;
  for (const std::vector<std::string> &arguments :
       {std::vector<std::string>{"--version"},
        std::vector<std::string>{"--set", "Method=dg", "command_line.prm"},
        std::vector<std::string>{"command_line.prm", "--set"},
        std::vector<std::string>{"--help", "command_line.prm"}})
    {
      std::ostringstream out, err;
      const int          code = app::run(arguments, out, err);
      std::cout << "* command line";
      for (const std::string &a : arguments)
        std::cout << ' ' << a;
      // The first line of the message; the usage text follows it.
      std::cout << ": exit code " << code << "\n  "
                << err.str().substr(0, err.str().find('\n')) << "\n"
                << std::endl;
    }
  std::ofstream("malformed.xml") << "<ParameterHandler><Method>";
  {
    std::ostringstream out, err;
    const int          code = app::run({"malformed.xml"}, out, err);
    std::cout << "* malformed_xml: exit code " << code << "\n  " << err.str()
              << std::endl;
  }
  // A closed tetrahedron whose corners coincide.
  std::ofstream("degenerate.obj") << "v 0 0 0\nv 0 0 0\nv 0 0 0\nv 0 0 0\n"
                                     "f 1 2 3\nf 1 3 4\nf 1 4 2\nf 2 4 3\n";
  run_case("degenerate_mesh", from_surface_mesh("degenerate.obj"));
  // A closed tetrahedron too large for its size to be a number.
  std::ofstream("huge.obj") << "v -1e308 0 0\nv 1e308 0 0\nv 0 1 0\nv 0 0 1\n"
                               "f 1 3 2\nf 1 2 4\nf 1 4 3\nf 2 3 4\n";
  run_case("huge_mesh",
           from_surface_mesh("huge.obj", "    set Fit to grid = true\n"));
  // A closed tetrahedron of subnormal size: the scale that fits it to the
  // grid overflows.
  std::ofstream("tiny.obj") << "v 0 0 0\nv 1e-310 0 0\nv 0 1e-310 0\n"
                               "v 0 0 1e-310\nf 1 3 2\nf 1 2 4\nf 1 4 3\n"
                               "f 2 3 4\n";
  run_case("tiny_mesh",
           from_surface_mesh("tiny.obj", "    set Fit to grid = true\n"));
  // Two faces of a tetrahedron: an open surface encloses nothing.
  std::ofstream("open.obj")
    << "v 0 0 0\nv 1 0 0\nv 0 1 0\nv 0 0 1\nf 1 2 3\nf 1 2 4\n";
  run_case("open_mesh", from_surface_mesh("open.obj"));
  // A closed tetrahedron written in millimeters: inside the grid's first
  // voxel, it encloses no voxel center. The shapes would have made the part
  // solid without the mesh.
  std::ofstream("millimeters.obj")
    << "v 0 0 0\nv 0.004 0 0\nv 0 0.004 0\nv 0 0 0.004\n"
       "f 1 3 2\nf 1 2 4\nf 1 4 3\nf 2 3 4\n";
  run_case("mesh_encloses_no_voxel",
           from_surface_mesh("millimeters.obj",
                             "    set Fit to grid = false\n  end\n"
                             "  set Shapes = box 0 0 0 0.02 0.04 0.02 : 2\n"
                             "  subsection Surface mesh\n"));
  // A binary STL whose header starts with "solid", cut short: neither its
  // size nor its text fits a format. Its floats hold 0 bytes and, in 0.01f
  // (0x3C23D70A), a line feed, which ends the "solid" line of an ASCII
  // reading.
  {
    std::ofstream stl("truncated.stl", std::ios::binary);
    stl << "solid made by an exporter" << std::string(55, ' ');
    const std::uint32_t n = 12;
    stl.write(reinterpret_cast<const char *>(&n), 4);
    for (unsigned int t = 0; t < 4; ++t)
      {
        const float normal_and_corners[12] = {
          0, 0, 1, 0, 0, 0, 0.01f, 0, 0, 0, 0.01f, 0};
        stl.write(reinterpret_cast<const char *>(normal_and_corners), 48);
        stl << std::string(2, '\0');
      }
  }
  run_case("truncated_binary_stl", from_surface_mesh("truncated.stl"));
  // A closed tetrahedron far larger than the 0.02 x 0.04 x 0.02 m grid:
  // without 'Fit to grid', most of it would be cut off.
  std::ofstream("too_large.obj")
    << "v 0 0 0\nv 0.16 0 0\nv 0 0.16 0\nv 0 0 0.16\n"
       "f 1 3 2\nf 1 2 4\nf 1 4 3\nf 2 3 4\n";
  run_case("mesh_outside_grid",
           from_surface_mesh("too_large.obj", "    set Fit to grid = false\n"));
  // An ASCII STL without facets, longer than a binary header: no triangles.
  std::ofstream("no_facets.stl")
    << "solid " << std::string(90, 'x') << "\nendsolid\n";
  run_case("ascii_stl_without_facets", from_surface_mesh("no_facets.stl"));
  // Messages name the line, counted with blank and comment lines.
  std::ofstream("bad_face.obj")
    << "# a tetrahedron\nv 0 0 0\nv 1 0 0\n\nv 0 1 0 # third\nv 0 0 1\n"
       "f 1 3 2\nf 1 2 7\n";
  run_case("obj_face_out_of_range", from_surface_mesh("bad_face.obj"));
  // A vertex line has 3 coordinates, then a weight or a colour at most.
  std::ofstream("bad_vertex.obj")
    << "v 0 0 0\nv 1 0 0 1 1\nv 0 1 0\nv 0 0 1\nf 1 3 2\nf 1 2 4\n";
  run_case("obj_vertex_with_two_extra_numbers",
           from_surface_mesh("bad_vertex.obj"));
  // An ASCII STL cut off between two facets: what it has is closed.
  {
    std::ofstream cut("cut_between_facets.stl");
    cut << "solid two parts\n";
    for (const auto &[a, b, c] : std::vector<std::array<const char *, 3>>{
           {{"0 0 0", "0 1 0", "1 0 0"}},
           {{"0 0 0", "1 0 0", "0 0 1"}},
           {{"0 0 0", "0 0 1", "0 1 0"}},
           {{"1 0 0", "0 1 0", "0 0 1"}}})
      cut << "facet normal 0 0 0\nouter loop\nvertex " << a << "\nvertex " << b
          << "\nvertex " << c << "\nendloop\nendfacet\n";
  }
  run_case("stl_cut_between_facets",
           from_surface_mesh("cut_between_facets.stl"));
  std::ofstream("vertex_outside_facet.stl")
    << "solid part\n\n  vertex 0 0 0\nendsolid part\n";
  run_case("stl_vertex_outside_facet",
           from_surface_mesh("vertex_outside_facet.stl"));
  std::ofstream("bad_id.txt") << "# ids\n2 4 2\n\n"
                              << "1 1 1 1 1 1 1 1 # first layer\n"
                              << "1 1 1 1 1 x 1 1\n";
  run_case("voxel_file_bad_id", from_voxel_file("bad_id.txt"));
  // The cantilever's palette has 3 materials; 16 voxels.
  const std::string fifteen_ids = "1 1 1 1 1 1 1 1 1 1 1 1 1 1 1";
  std::ofstream("id_out_of_range.txt") << "2 4 2\n" << fifteen_ids << " 4\n";
  run_case("voxel_file_id_out_of_range",
           from_voxel_file("id_out_of_range.txt"));
  std::ofstream("too_few_ids.txt") << "2 4 2\n" << fifteen_ids << "\n";
  run_case("voxel_file_too_few_ids", from_voxel_file("too_few_ids.txt"));
  std::ofstream("too_many_ids.txt") << "2 4 2\n" << fifteen_ids << " 1 1\n";
  run_case("voxel_file_too_many_ids", from_voxel_file("too_many_ids.txt"));
  // Windows line ends: the quoted line shows no carriage return.
  std::ofstream("bad_header.txt") << "2 4 x\r\n" << fifteen_ids << " 1\r\n";
  run_case("voxel_file_bad_header", from_voxel_file("bad_header.txt"));
  std::ofstream("header_with_ids.txt") << "2 4 2 " << fifteen_ids << " 1\n";
  run_case("voxel_file_header_with_ids",
           from_voxel_file("header_with_ids.txt"));
  // Old Mac line ends (carriage returns only) make an OBJ file one line:
  // the message quotes its first 80 characters.
  std::ofstream("carriage_returns.obj")
    << "v 0.000 0.000 0.000\rv 1.000 0.000 0.000\rv 0.000 1.000 0.000\r"
       "v 0.000 0.000 1.000\rf 1 3 2\rf 1 2 4\rf 1 4 3\rf 2 3 4\r";
  run_case("obj_with_carriage_returns_only",
           from_surface_mesh("carriage_returns.obj"));
  run_case("surface_mesh_unknown_extension", from_surface_mesh("part.ply"));
  std::ofstream("damaged.h5.journal") << "not a journal\n";
  run_case("damaged_journal",
           cantilever,
           {"--set", "Method=ddfem", "--set", "Database/File=damaged.h5"});
  std::cout << "  database written: " << std::filesystem::exists("damaged.h5")
            << ", journal kept: "
            << std::filesystem::exists("damaged.h5.journal") << "\n"
            << std::endl;

  // A build stopped by a fit refused for its settings removes the journal
  // it started (a killed build keeps it: tests/coarsening/database.cc):
  // the same settings refuse the fit again. The rerun with valid settings
  // then runs.
  {
    std::filesystem::remove_all("refused");
    const std::string layers =
      cantilever + testing::cheap_lazy_database("refused/db.h5") +
      "set Method = ddfem\nsubsection Layout\n  set Type = layers\n"
      "  subsection Layers\n    set Axis = y\n    set Materials = 1, 2\n"
      "    set Thickness = 0.01\n  end\nend\n";
    run_case("fit_refused",
             layers,
             {"--set", "Database/Fitting/Regularization=0"},
             true);
    std::cout << "  journal kept: "
              << std::filesystem::exists("refused/db.h5.journal") << "\n"
              << std::endl;
    run_case("rerun_after_refused_fit", layers);
  }

  // Not an error: a probe 4e-10 voxel sizes off the tip, within the
  // tolerance of 1e-9 voxel sizes, in the fine and a coarse model alike
  // (their searches used deal.II's tolerance, 1e-10 of a cell, and
  // rejected it).
  for (const std::string method : {"fine", "naive"})
    run_case("probe_within_tolerance_" + method,
             cantilever + "set Method = " + method +
               "\nsubsection Geometry\n  set Probe points = 0.01, "
               "0.040000000004, 0.01\nend\n");

  // Not an error: white space between words is free.
  run_case(
    "extra_spaces_are_fine",
    cantilever +
      "subsection Materials\n  set Palette = E=1e5   nu=0.3\nend\n"
      "subsection Layout\n  set Shapes = box  0 0 0   0.02 0.02 0.02 : 1\nend\n");

  // Not an error: at degree 2 a support may hold only midpoint nodes, here
  // the plane half a voxel from the clamped end.
  run_case("degree_2_support_on_midpoints",
           cantilever +
             "subsection Discretization\n  set Polynomial degree = 2\nend\n"
             "subsection Boundary conditions\n  subsection Condition 1\n"
             "    set Region = box -1 0.004 -1 1 0.006 1\n  end\nend\n");

  // Scenes that cannot be solved, caught before any solve.
  run_case("all_void",
           cantilever + "subsection Layout\n  set Material = 0\nend\n");
  run_case("no_dirichlet",
           cantilever +
             "subsection Boundary conditions\n  subsection Condition 1\n"
             "    set Type = none\n  end\nend\n");
  run_case("floor_only",
           cantilever +
             "subsection Boundary conditions\n  subsection Condition 1\n"
             "    set Type = sliding\n    set Region = z-\n  end\nend\n");
  const std::string floating_voxels = R"(
subsection Geometry
  set Grid size = 4, 8, 4
end
subsection Layout
  set Shapes = box 0.02 0.03 0 0.04 0.05 0.04 : 0; box 0.02 0.05 0 0.04 0.08 0.04 : 0; box 0 0.03 0 0.04 0.05 0.04 : 0
end
subsection Boundary conditions
  subsection Condition 1
    set Type = fixed
    set Region = y-
  end
end
)";
  run_case("floating_voxels", floating_voxels);
  // Coarse blocks may bridge the gap; the voxels are checked as they are.
  run_case("floating_voxels_naive", floating_voxels, {"--set", "Method=naive"});
  // Held in part by conditions of their own: the message asks for more.
  run_case("partly_held_voxels",
           floating_voxels +
             "subsection Boundary conditions\n  subsection Condition 2\n"
             "    set Type = sliding\n    set Region = z-\n  end\nend\n");
  // Not bad input but a solve that fails: rigid blocks on soft hinges
  // (contrast 1e6) bent far in few, short Newton runs. It must stop with a
  // message naming what failed; the converged load steps are kept.
  // Both cases bend a longer cantilever far.
  const std::string bent_far = cantilever + R"(
subsection Geometry
  set Grid size = 2, 12, 2
end
subsection Boundary conditions
  subsection Condition 2
    set Value = 0; 0; -3e3
  end
end
)";
  run_case("unconverged", bent_far + R"(
subsection Materials
  set Palette = E=1e5 nu=0.45; E=1e11 nu=0.45
end
subsection Layout
  set Type = layers
  subsection Layers
    set Thickness = 0.02
    set Materials = 1, 2
  end
end
subsection Nonlinear solver
  set Load steps = 2
  set Maximum Newton iterations = 8
  set Minimum load step = 0.1
end
)");
  // A linear solver that fails on the tangent (CG limited to one
  // iteration, toward a reduction of 1e-12, on a grid whose 2793 unknowns
  // ML does not solve on its coarsest level) and succeeds only on the
  // tangent shifted by 1e4 times its diagonal: every Newton iteration is
  // shifted, and after 8 of them the increment fails. The message says
  // why, not only that the step failed.
  run_case("linear_solver_fails",
           cantilever,
           {"--set",
            "Geometry/Grid size=6, 18, 6",
            "--set",
            "Linear solver/Type=cg-amg",
            "--set",
            "Linear solver/Tolerance=1e-12",
            "--set",
            "Linear solver/Maximum iterations=1",
            "--set",
            "Nonlinear solver/Load steps=1",
            "--set",
            "Nonlinear solver/Minimum load step=1"});
  // A solve that converges in its first load step and fails in its second
  // (a soft cantilever bent far, Newton's method limited, no cutting)
  // keeps the converged step: its VTU file and a summary.json that says so.
  // A comparison whose models do not converge says so on the error stream.
  run_case("compare_unconverged",
           bent_far,
           {"--set",
            "Run type=compare",
            "--set",
            "Comparison/Methods=",
            "--set",
            "Nonlinear solver/Load steps=1",
            "--set",
            "Nonlinear solver/Minimum load step=1",
            "--set",
            "Nonlinear solver/Maximum Newton iterations=1"});
  // The directory of the solve that fails in its second step holds the VTU
  // file of a step it does not reach, left by an earlier run: the run
  // removes it (it is no result of this run).
  std::filesystem::remove_all("out_unconverged_later");
  std::filesystem::create_directory("out_unconverged_later");
  std::ofstream("out_unconverged_later/solution-0003.vtu") << "earlier run\n";
  run_case("unconverged_later",
           bent_far + R"(
subsection Nonlinear solver
  set Load steps = 5
  set Maximum Newton iterations = 16
  set Minimum load step = 1
end
subsection Output
  set Write VTU = every step
end
)",
           {},
           false,
           true);
  {
    std::ifstream        file("out_unconverged_later/summary.json");
    const nlohmann::json summary = nlohmann::json::parse(file);
    std::cout
      << "  summary.json: converged " << std::boolalpha
      << summary.at("converged").get<bool>() << ", load steps "
      << summary.at("load_steps").get<unsigned int>()
      << "; VTU of step 1 written: "
      << std::filesystem::exists("out_unconverged_later/solution-0001.vtu")
      << ", of step 2: "
      << std::filesystem::exists("out_unconverged_later/solution-0002.vtu")
      << "; earlier run's VTU of step 3 left: "
      << std::filesystem::exists("out_unconverged_later/solution-0003.vtu")
      << std::endl;
  }
  // Whatever Write VTU says, a run removes the VTU files an earlier run left:
  // of every state, also states this run does not have (the cantilever has
  // no edits), and another model's too (a DG run writes solution.vtu, a
  // continuous one solution.pvd and its steps). None of them may be taken
  // for this run's. A file of another name stays. (The compare run writes
  // VTU files: what counts is whether the earlier ones' text is left.)
  const auto run_with_earlier_vtu =
    [](const std::string              &name,
       const std::string              &prm,
       const std::vector<std::string> &extra,
       const std::vector<std::string> &earlier) {
      const std::string directory = "out_" + name;
      std::filesystem::remove_all(directory);
      for (const std::string &file : earlier)
        {
          std::filesystem::create_directories(
            std::filesystem::path(directory + "/" + file).parent_path());
          std::ofstream(directory + "/" + file) << "earlier run\n";
        }
      run_case(name, prm, extra, false, true);
      std::cout << "  earlier files left:";
      for (const std::string &file : earlier)
        {
          if (testing::content_of(directory + "/" + file) == "earlier run\n")
            std::cout << ' ' << file;
        }
      std::cout << "\n" << std::endl;
    };
  // A simulation removes a comparison's results too.
  for (const std::string method : {"fine", "dg"})
    run_with_earlier_vtu("stale_vtu_" + method,
                         cantilever + "set Method = " + method + "\n",
                         {"--set", "Output/Write VTU=none"},
                         {"solution.pvd",
                          "solution-0001.vtu",
                          "solution.vtu",
                          "edit-3.pvd",
                          "edit-3-0001.vtu",
                          "notes.vtu",
                          "comparison.csv",
                          "error_vs_time.png",
                          "naive-L1/solution-0001.vtu",
                          "fine-direct/solution.pvd"});
  // Not an error: a result named by a symbolic link to nowhere is replaced,
  // as an earlier result is, and the check before the run makes no file
  // at the link's target (it made one, and removed the link).
  {
    const std::string directory = "out_summary_dangling_link";
    std::filesystem::remove_all(directory);
    std::filesystem::create_directories(directory);
    std::filesystem::create_symlink("nowhere.json",
                                    directory + "/summary.json");
    write_prm("summary_dangling_link.prm", cantilever, directory, "none");
    std::ostringstream out, err;
    const int          code = app::run({"summary_dangling_link.prm"}, out, err);
    std::cout << "* summary_dangling_link: exit code " << code
              << ", summary.json a regular file: " << std::boolalpha
              << std::filesystem::is_regular_file(
                   std::filesystem::symlink_status(directory + "/summary.json"))
              << ", a file made at the link's target: "
              << std::filesystem::exists(directory + "/nowhere.json") << "\n"
              << err.str() << std::endl;
    std::filesystem::remove_all(directory);
  }
  // Results that could not be written are found before anything runs: the
  // output directory keeps only what was there.
  run_in_existing_directory("summary_blocked", "summary.json", cantilever, {});
  // Also where a result is written first (it used to be found only once
  // the solve was done, with a message naming the result).
  run_in_existing_directory("summary_partial_blocked",
                            "summary.json.partial/x",
                            cantilever,
                            {});
  run_in_existing_directory("parameters_partial_blocked",
                            "parameters.prm.partial/x",
                            cantilever,
                            {});
  const std::vector<std::string> compare_naive = {"--set",
                                                  "Run type=compare",
                                                  "--set",
                                                  "Comparison/Methods=naive",
                                                  "--set",
                                                  "Comparison/Levels=1"};
  run_in_existing_directory("comparison_blocked",
                            "comparison.csv",
                            cantilever,
                            compare_naive);
  // A compare run removes the VTU files of models it does not compare too,
  // and a simulation's results in its output directory.
  run_with_earlier_vtu("stale_vtu_compare",
                       cantilever,
                       compare_naive,
                       {"summary.json",
                        "solution.pvd",
                        "naive-L2/solution.pvd",
                        "ddfem-L1/edit-1-0002.vtu",
                        "fine/edit-2-0001.vtu"});
  // Level 2 of a lazily built database needs a grid divisible by 4: an
  // error before anything is fitted, so that no build journal is left to
  // stand in the way of the next build, and before the lock makes the
  // file's directory and lock file.
  std::filesystem::remove_all("level2_grid");
  run_case("database_level2_grid",
           cantilever + "set Run type = database\n" +
             testing::cheap_lazy_database("level2_grid/db.h5") +
             "subsection Database\n  set Levels = 2\nend\n");
  std::cout << "  database directory made: "
            << std::filesystem::exists("level2_grid") << "\n"
            << std::endl;
  // So is a 4x4x4 block with void and solid 2x2x2 blocks in a database
  // without void: level 1 has all its blocks, level 2 none for it.
  std::filesystem::remove_all("level2_void");
  run_case("database_level2_void_without_void",
           testing::cantilever("4, 8, 4", "0; 0; -100") +
             "set Run type = database\n" +
             testing::cheap_lazy_database("level2_void/db.h5") +
             "subsection Database\n  set Levels = 2\n"
             "  set Include void = false\nend\n"
             "subsection Layout\n  set Shapes = box 0 0.04 0.02 0.04 0.08 "
             "0.04 : 0\nend\n");
  std::cout << "  database directory made: "
            << std::filesystem::exists("level2_void") << "\n"
            << std::endl;
  // So are a simulation's and a compare run's, which fit lazily.
  for (const std::string run : {"simulation", "compare"})
    {
      const std::string directory = "level2_void_" + run;
      std::filesystem::remove_all(directory);
      run_case("database_level2_void_without_void_" + run,
               testing::cantilever("4, 8, 4", "0; 0; -100") +
                 "set Run type = " + run +
                 "\nset Method = ddfem\nset Coarsening levels = 2\n"
                 "subsection Comparison\n  set Methods = ddfem\n"
                 "  set Levels = 2\nend\n" +
                 testing::cheap_lazy_database(directory + "/db.h5") +
                 "subsection Database\n  set Include void = false\nend\n"
                 "subsection Layout\n  set Shapes = box 0 0.04 0.02 0.04 "
                 "0.08 0.04 : 0\nend\n");
      std::cout << "  database directory made: "
                << std::filesystem::exists(directory) << "\n"
                << std::endl;
    }
  // So are VTU files of any load step (the message names the file; deal.II's
  // writers would throw a generic input/output error), of an edited state,
  // of a DG solve and of a compare run's model.
  const std::vector<std::string> every_step = {"--set",
                                               "Output/Write VTU=every step"};
  run_in_existing_directory("vtu_blocked",
                            "solution-0003.vtu",
                            cantilever,
                            every_step);
  run_in_existing_directory(
    "edit_vtu_blocked",
    "edit-1.pvd",
    cantilever +
      "subsection Layout\n  set Edits = box -1 -1 -1 1 1 1 : 2\nend\n",
    every_step);
  run_in_existing_directory("dg_vtu_blocked",
                            "solution.vtu",
                            cantilever + "set Method = dg\n",
                            every_step);
  std::vector<std::string> compare_vtu = compare_naive;
  compare_vtu.insert(compare_vtu.end(), every_step.begin(), every_step.end());
  run_in_existing_directory("compare_vtu_blocked",
                            "naive-L1/solution-0001.vtu",
                            cantilever,
                            compare_vtu);
  // So is a file in the way of a model's VTU directory: the fine models,
  // solved first, would leave their directories.
  run_in_existing_directory(
    "compare_vtu_directory_blocked", "", cantilever, compare_vtu, "naive-L1");
  // A DG study of one problem removes an earlier study's figure of the
  // other.
  run_in_existing_directory(
    "dg_study_stale",
    "",
    "set Run type = dg convergence\nsubsection DG convergence\n"
    "  set Problems = 2D Poisson\n  set Methods = IP lin\n"
    "  set 2D refinements = 1, 2\nend\n",
    {},
    "dg_convergence_3D_elasticity.png");
  // A study removes a simulation's results, and a simulation a study's,
  // and a study writes its parameters.prm (an earlier run's stayed).
  run_in_existing_directory(
    "dg_study_after_simulation",
    "",
    "set Run type = dg convergence\nsubsection DG convergence\n"
    "  set Problems = 2D Poisson\n  set Methods = IP lin\n"
    "  set 2D refinements = 1, 2\nend\n",
    {},
    "summary.json");
  run_in_existing_directory(
    "simulation_after_dg_study", "", cantilever, {}, "dg_cost.txt");
  // A study whose settings are wrong removes nothing.
  run_in_existing_directory(
    "dg_study_bad_refinements",
    "",
    "set Run type = dg convergence\nsubsection DG convergence\n"
    "  set 2D refinements = 3, 1\nend\n",
    {},
    "summary.json");
  // Study sizes whose matrices alone could not fit into this machine's
  // memory (24 GiB): refused before anything is assembled.
  run_case("dg_study_too_fine",
           "set Run type = dg convergence\nsubsection DG convergence\n"
           "  set 3D refinements = 1, 7\nend\n");
  run_case("dg_cost_too_fine",
           "set Run type = dg cost\nsubsection DG\n  set Penalty = 8\nend\n"
           "subsection DG cost\n  set Resolution = 100\nend\n");
  // Another run's results where a compare run keeps a model's VTU files:
  // a simulation or compare run into the parent removed its VTU files (or
  // a compare run added its own), and left the rest of that run's results.
  // Nor may a run write into a compare run's model directory. (The runs
  // write into model_directories, which "output written" does not see:
  // the listing shows what is there.)
  {
    const std::string parent = "model_directories", fine = parent + "/fine";
    const std::string file = parent + ".prm";
    std::ofstream(file) << cantilever
                        << "subsection Output\n  set Screen timings = "
                           "false\nend\n";
    const auto into = [&](const std::string              &directory,
                          const std::vector<std::string> &extra) {
      std::vector<std::string> arguments = {
        file, "--set", "Output/Output directory=" + directory};
      arguments.insert(arguments.end(), extra.begin(), extra.end());
      return arguments;
    };
    const auto list = [&](const std::string &directory) {
      std::cout << "  " << directory << " holds:" << listing(directory) << "\n"
                << std::endl;
    };
    std::ostringstream ignored;
    std::filesystem::remove_all(parent);
    app::run(into(fine, {}), ignored, ignored);
    report_run("other_run_in_model_directory", into(parent, {}));
    report_run("other_run_in_model_directory_compare",
               into(parent, compare_naive));
    list(parent);
    list(fine);
    std::filesystem::remove_all(parent);
    app::run(into(parent, compare_naive), ignored, ignored);
    report_run("run_into_model_directory", into(fine, {}));
    // The same directory through a link.
    std::filesystem::remove("link_to_fine");
    std::filesystem::create_directory_symlink(fine, "link_to_fine");
    report_run("run_into_model_directory_link", into("link_to_fine", {}));
    list(fine);
  }
  // A run that fails once it has begun to write results (here the first
  // VTU file cannot be written) removes them again, with the directories
  // it made for them.
  const std::string larger = testing::cantilever("4, 12, 4", "0; 0; -100");
  run_with_small_files("vtu_fails_fine", larger, {});
  run_with_small_files("vtu_fails_dg", larger, {"--set", "Method=dg"});
  run_with_small_files("vtu_fails_compare", larger, compare_naive);
  // A rerun from the parameters.prm of a run that fails the same way puts
  // that file back as it was: it is the rerun's input (it used to be
  // removed with the rerun's results).
  {
    std::filesystem::remove_all("out_rerun_fails");
    write_prm("rerun_fails.prm", larger, "out_rerun_fails", "none");
    std::ostringstream out, err;
    const int          first = app::run({"rerun_fails.prm"}, out, err);
    const std::string  used =
      testing::content_of("out_rerun_fails/parameters.prm");
    std::ostringstream rerun_err;
    const int code = run_with_small_files({"out_rerun_fails/parameters.prm",
                                           "--set",
                                           "Output/Write VTU=every step"},
                                          rerun_err);
    std::cout << "* rerun_fails: first run's exit code " << first
              << ", the rerun's " << code
              << ", out_rerun_fails holds:" << listing("out_rerun_fails")
              << ", parameters.prm as the first run wrote it: "
              << (!used.empty() &&
                  testing::content_of("out_rerun_fails/parameters.prm") == used)
              << "\n  " << rerun_err.str() << std::endl;
  }
  // A compare run that fails so removes an earlier simulation's
  // parameters.prm with its results (it stayed, alone, as if it described
  // what is there), and keeps the one it was started from.
  {
    std::filesystem::remove_all("out_compare_fails");
    write_prm("compare_fails.prm", larger, "out_compare_fails", "none");
    std::ostringstream out, err;
    const int          simulation = app::run({"compare_fails.prm"}, out, err);
    std::vector<std::string> arguments = {"compare_fails.prm",
                                          "--set",
                                          "Output/Write VTU=every step"};
    arguments.insert(arguments.end(),
                     compare_naive.begin(),
                     compare_naive.end());
    std::ostringstream compare_err;
    const int          code = run_with_small_files(arguments, compare_err);
    std::cout << "* compare_fails_after_simulation: the simulation's exit code "
              << simulation << ", the comparison's " << code
              << ", out_compare_fails holds:" << listing("out_compare_fails")
              << "\n  " << compare_err.str() << std::endl;

    std::vector<std::string> compare = {"compare_fails.prm"};
    compare.insert(compare.end(), compare_naive.begin(), compare_naive.end());
    const int         first = app::run(compare, out, err);
    const std::string used =
      testing::content_of("out_compare_fails/parameters.prm");
    arguments[0] = "out_compare_fails/parameters.prm";
    std::ostringstream rerun_err;
    const int          rerun = run_with_small_files(arguments, rerun_err);
    std::cout << "* compare_rerun_fails: first run's exit code " << first
              << ", the rerun's " << rerun
              << ", out_compare_fails holds:" << listing("out_compare_fails")
              << ", parameters.prm as the first run wrote it: "
              << (!used.empty() &&
                  testing::content_of("out_compare_fails/parameters.prm") ==
                    used)
              << "\n  " << rerun_err.str() << std::endl;
  }
  // Where the input cannot be put back either (here it is larger than a
  // file may grow), parameters.prm keeps the rerun's parameters: the
  // restore replaces it in one rename, and no longer removes it first.
  {
    std::ofstream("out_rerun_fails/parameters.prm", std::ios::app)
      << "# " << std::string(12000, '-') << "\n";
    std::ostringstream err;
    const int code = run_with_small_files({"out_rerun_fails/parameters.prm",
                                           "--set",
                                           "Output/Write VTU=every step"},
                                          err);
    const std::string kept =
      testing::content_of("out_rerun_fails/parameters.prm");
    std::cout << "* rerun_fails_restore_too: exit code " << code
              << ", parameters.prm holds the rerun's parameters: "
              << (kept.find("= every step") != std::string::npos &&
                  kept.find("# ---") == std::string::npos)
              << std::endl;
  }
  // A gnuplot that does not work is found before anything runs too.
  {
    std::filesystem::create_directories("broken_bin");
    std::ofstream("broken_bin/gnuplot") << "#!/bin/sh\nexit 1\n";
    std::filesystem::permissions("broken_bin/gnuplot",
                                 std::filesystem::perms::owner_all);
    const std::string path = std::getenv("PATH");
    setenv(
      "PATH",
      (std::filesystem::absolute("broken_bin").string() + ":" + path).c_str(),
      1);
    run_in_existing_directory("broken_gnuplot", "", cantilever, compare_naive);
    // The same for a DG convergence study, which draws its figures last.
    run_in_existing_directory("broken_gnuplot_dg_study",
                              "",
                              "set Run type = dg convergence\nsubsection DG "
                              "convergence\n  set Problems = 2D Poisson\n"
                              "  set Methods = IP lin\n  set 2D refinements "
                              "= 1, 2\nend\n",
                              {});
    // Not bad input: a comparison of the fine solvers alone draws no plot
    // (it needs no gnuplot) and leaves no plot files, but writes its table
    // and parameters.
    run_in_existing_directory(
      "fine_solvers_only",
      "",
      cantilever,
      {"--set", "Run type=compare", "--set", "Comparison/Methods="});
    setenv("PATH", path.c_str(), 1);
  }
  // Not bad input: a fine run does not read the database settings.
  run_case("fine_ignores_database_settings",
           cantilever,
           {"--set",
            "Database/File=",
            "--set",
            "Discretization/Coarse point offset=1"});
  run_case(
    "duplicate_methods",
    cantilever,
    {"--set", "Run type=compare", "--set", "Comparison/Methods=naive, naive"});
  run_case("duplicate_levels",
           cantilever,
           {"--set", "Run type=compare", "--set", "Comparison/Levels=1, 1"});
  // Voxels of a grid of @p grid_size laid out by @p shapes, clamped at
  // x = 0 and loaded by nothing: only the checks before a solve can fail.
  const auto clamped_at_x0 = [](const std::string &grid_size,
                                const std::string &shapes) {
    return "subsection Geometry\n  set Grid size = " + grid_size +
           "\nend\nsubsection Layout\n  set Shapes = " + shapes +
           "\nend\nsubsection Boundary conditions\n  subsection Condition "
           "1\n    set Type = fixed\n    set Region = x-\n  end\nend\n";
  };
  run_case("edge_hinge",
           clamped_at_x0("2, 2, 1",
                         "box 0.01 0 0 0.02 0.01 0.01 : 0; box 0 0.01 0 0.01 "
                         "0.02 0.01 : 0"));
  // Two parts that hold each other up (they share an edge along z and one
  // along x) but hang on the clamped voxel along one edge together: each
  // is held by the nodes it shares, the two turn about that edge as one.
  run_case("hinged_group",
           clamped_at_x0("3, 3, 3",
                         "box 0 0 0 0.03 0.03 0.03 : 0; box 0 0 0 0.01 0.01 "
                         "0.01 : 1; box 0.01 0.01 0 0.02 0.02 0.02 : 1; box "
                         "0.02 0.02 0 0.03 0.03 0.03 : 1; box 0.01 0.02 0.02 "
                         "0.02 0.03 0.03 : 1"));
  // deal.II's split_string_list() drops a last empty entry: an extra
  // separator at the end of a pair, a shape or a list is an error, as one
  // in the middle is.
  run_case("pair_with_trailing_equals",
           cantilever +
             "subsection Materials\n  set Palette = E=1e5= nu=0.3\nend\n");
  run_case("shape_with_trailing_colon",
           cantilever + "subsection Layout\n  set Shapes = box 0 0 0 0.01 "
                        "0.01 0.01 : 1 :\nend\n");
  run_case("trailing_comma_in_list",
           cantilever,
           {"--set", "Run type=compare", "--set", "Comparison/Levels=1,2,"});
  run_case("trailing_slash_in_set", cantilever, {"--set", "Method/=naive"});
  // A coarse model solves the scene the fine model would: its blocks may
  // bridge the edge joint, or reach the grid's face where the solid ends
  // short of it, but the scene is rejected as the fine model rejects it.
  const std::string column = testing::cantilever("4, 16, 4", "0; 0; -2");
  run_case("edge_joint_coarse",
           column + "subsection Layout\n  set Shapes = box 0.03 0 0 0.04 "
                    "0.09 0.04 : 0; box 0 0.09 0 0.03 0.16 0.04 : 0\nend\n",
           {"--set", "Method=naive"});
  run_case("region_beyond_the_solid_coarse",
           column + "subsection Layout\n  set Shapes = box 0 0.15 0 0.04 "
                    "0.16 0.04 : 0\nend\n",
           {"--set",
            "Method=average",
            "--set",
            "Boundary conditions/Condition 2/Type=displacement",
            "--set",
            "Boundary conditions/Condition 2/Value=0; 0; -0.001"});
}
