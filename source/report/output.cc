#include <deal.II/base/data_out_base.h>
#include <deal.II/numerics/data_out.h>

#include <ddfem/base/files.h>
#include <ddfem/report/output.h>
#include <fcntl.h>
#include <spawn.h>
#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <array>
#include <cctype>
#include <cerrno>
#include <filesystem>
#include <sstream>

namespace ddfem::report
{
  namespace
  {
    /**
     * Runs gnuplot with its default settings (not the user's ~/.gnuplot,
     * which could change how the scripts read their data) and the
     * arguments @p arguments in @p directory, without a shell (the
     * directory is user input), its standard output and error to /dev/null
     * if @p quiet. Returns whether it ran and
     * exited with 0. Throws ExcMessage naming @p what and the Debian
     * package if it cannot be started.
     */
    bool
    gnuplot_succeeds(const std::string              &directory,
                     const std::vector<std::string> &arguments,
                     const bool                      quiet,
                     const std::string              &what)
    {
      posix_spawn_file_actions_t actions;
      posix_spawn_file_actions_init(&actions);
      posix_spawn_file_actions_addchdir_np(&actions, directory.c_str());
      if (quiet)
        for (const int stream : {STDOUT_FILENO, STDERR_FILENO})
          posix_spawn_file_actions_addopen(
            &actions, stream, "/dev/null", O_WRONLY, 0);
      std::vector<std::string> words = {"gnuplot", "--default-settings"};
      words.insert(words.end(), arguments.begin(), arguments.end());
      std::vector<char *> argv;
      for (std::string &word : words)
        argv.push_back(word.data());
      argv.push_back(nullptr);
      pid_t     pid;
      const int error =
        posix_spawnp(&pid, "gnuplot", &actions, nullptr, argv.data(), environ);
      posix_spawn_file_actions_destroy(&actions);
      AssertThrow(error == 0,
                  ExcMessage("gnuplot could not be started " + what +
                             ": it comes from the Debian package "
                             "gnuplot-nox, which scripts/setup.sh installs."));
      int   status = 0;
      pid_t waited;
      do
        waited = waitpid(pid, &status, 0);
      while (waited == -1 && errno == EINTR);
      return waited == pid && WIFEXITED(status) && WEXITSTATUS(status) == 0;
    }
  } // namespace



  void
  check_gnuplot(const std::string &run_type)
  {
    // The terminal of the plot: a gnuplot built without cairo would fail
    // only once everything has been solved.
    AssertThrow(gnuplot_succeeds(".",
                                 {"-e",
                                  "set terminal pngcairo; set output "
                                  "'/dev/null'; plot 1"},
                                 true,
                                 "(Run type = " + run_type +
                                   " draws its plots with it)"),
                ExcMessage("gnuplot could not draw with its pngcairo "
                           "terminal: the plots of Run type = " +
                           run_type +
                           " could not be drawn. Reinstall the Debian "
                           "package gnuplot-nox."));
  }



  void
  run_gnuplot(const std::string              &directory,
              const std::string              &script,
              const std::vector<std::string> &images)
  {
    const bool drawn =
      gnuplot_succeeds(directory,
                       {script},
                       false,
                       "to draw \"" + directory + "/" + script + "\"");
    // Best effort: the error to report is gnuplot's.
    if (!drawn)
      for (const std::string &image : images)
        {
          std::error_code ignored;
          std::filesystem::remove(directory + "/" + image, ignored);
        }
    AssertThrow(drawn,
                ExcMessage("gnuplot failed on \"" + directory + "/" + script +
                           "\" (its message is above)."));
  }



  std::string
  gnuplot_string(const std::string &text)
  {
    std::string quoted = "'";
    for (const char c : text)
      quoted += c == '\'' ? std::string("''") :
                std::iscntrl(static_cast<unsigned char>(c)) ?
                             std::string(" ") : // a newline would end the line
                             std::string(1, c);
    return quoted + "'";
  }



  std::string
  gnuplot_style(const unsigned int series)
  {
    static const std::array<unsigned int, 8> point_types = {
      {5, 7, 9, 11, 13, 15, 1, 2}};
    static const std::array<const char *, 8> colours = {{"#0072B2",
                                                         "#D55E00",
                                                         "#009E73",
                                                         "#CC79A7",
                                                         "#E69F00",
                                                         "#56B4E9",
                                                         "#000000",
                                                         "#999999"}};
    return "pt " + std::to_string(point_types[series % 8]) + " lc rgb '" +
           colours[series % 8] + "'";
  }



  void
  VtuWriter::declare_parameters(ParameterHandler &prm)
  {
    prm.enter_subsection("Output");
    prm.declare_entry(
      "Write VTU",
      "every step",
      Patterns::Selection("every step|last step|none"),
      "Which load steps are written as VTU files (with a .pvd record).");
    prm.leave_subsection();
  }



  void
  VtuWriter::parse_parameters(ParameterHandler &prm)
  {
    prm.enter_subsection("Output");
    when = prm.get("Write VTU");
    prm.leave_subsection();
  }



  std::string
  VtuWriter::state_name(const unsigned int state)
  {
    return state == 0 ? "solution" : "edit-" + std::to_string(state);
  }



  void
  VtuWriter::initialize(const std::string &dir, const unsigned int state)
  {
    directory = dir;
    basename  = state_name(state);
    records.clear();
  }



  namespace
  {
    /// Whether @p text is a nonempty string of decimal digits.
    bool
    is_number(const std::string &text)
    {
      return !text.empty() &&
             std::all_of(text.begin(), text.end(), [](const char c) {
               return std::isdigit(static_cast<unsigned char>(c));
             });
    }

    /// Whether @p name is a scene state's (VtuWriter::state_name()).
    bool
    is_state_name(const std::string &name)
    {
      return name == "solution" ||
             (name.rfind("edit-", 0) == 0 && is_number(name.substr(5)));
    }
  } // namespace



  bool
  VtuWriter::is_vtu_file(const std::string &name)
  {
    std::string       file    = name;
    const std::string partial = ResultFile::partial_name("");
    if (file.size() > partial.size() &&
        file.compare(file.size() - partial.size(), partial.size(), partial) ==
          0)
      file.resize(file.size() - partial.size());
    if (file.size() < 4)
      return false;
    const std::string stem      = file.substr(0, file.size() - 4),
                      extension = file.substr(file.size() - 4);
    if (extension != ".pvd" && extension != ".vtu")
      return false;
    if (is_state_name(stem))
      return true;
    const std::size_t dash = stem.rfind('-');
    return extension == ".vtu" && dash != std::string::npos &&
           is_number(stem.substr(dash + 1)) &&
           is_state_name(stem.substr(0, dash));
  }



  std::vector<std::string>
  VtuWriter::existing_files(const std::string &dir)
  {
    std::vector<std::string> files;
    std::error_code          error;
    // Not a directory (missing, or a file in the way, which
    // check_creatable() finds where this run writes): no earlier files.
    if (!std::filesystem::is_directory(dir, error))
      return files;
    for (std::filesystem::directory_iterator entry(dir, error), end;
         !error && entry != end;
         entry.increment(error))
      if (is_vtu_file(entry->path().filename().string()))
        files.push_back(entry->path().string());
    AssertThrow(!error,
                ExcMessage("Cannot list the directory '" + dir +
                           "' (Output/Output directory) for the VTU files "
                           "of an earlier run: " +
                           error.message()));
    std::sort(files.begin(), files.end());
    return files;
  }



  void
  VtuWriter::check_writable(const std::string &dir,
                            const unsigned int n_states) const
  {
    const std::string where = "Output/Output directory";
    if (enabled())
      for (unsigned int state = 0; state < n_states; ++state)
        ddfem::check_writable(dir + "/" + state_name(state) + ".pvd", where);
    for (const std::string &file : existing_files(dir))
      ddfem::check_writable(file, where);
  }



  void
  VtuWriter::remove_earlier(const std::string &dir)
  {
    for (const std::string &file : existing_files(dir))
      ddfem::remove_earlier(file, "Output/Output directory");
  }



  void
  add_displacement_and_materials(DataOut<3>           &data_out,
                                 const DoFHandler<3>  &dof_handler,
                                 const Vector<double> &u,
                                 Vector<double>       &material_id)
  {
    const auto &triangulation = dof_handler.get_triangulation();
    material_id.reinit(triangulation.n_active_cells());
    for (const auto &cell : triangulation.active_cell_iterators())
      material_id(cell->active_cell_index()) = cell->material_id();
    data_out.attach_dof_handler(dof_handler);
    data_out.add_data_vector(
      u,
      std::vector<std::string>(3, "displacement"),
      DataOut<3>::type_dof_data,
      std::vector<DataComponentInterpretation::DataComponentInterpretation>(
        3, DataComponentInterpretation::component_is_part_of_vector));
    data_out.add_data_vector(material_id, "material_id");
  }



  void
  write_vtu_file(DataOut<3> &data_out, const std::string &file)
  {
    DataOutBase::VtkFlags flags;
    flags.print_date_and_time = false;
    data_out.set_flags(flags);
    // deal.II's writers throw a generic ExcIO on a stream that did not
    // open, which ResultFile checks first, or that failed while they wrote
    // (a full disk): commit() then names the file.
    ResultFile out(file, "Output/Output directory");
    try
      {
        data_out.write_vtu(out.stream());
      }
    catch (const StandardExceptions::ExcIO &)
      {
        AssertThrow(!out.stream(), ExcInternalError());
      }
    out.commit();
  }



  void
  VtuWriter::write(const solver::Discretization           &discretization,
                   const Vector<double>                   &u,
                   const solver::StaticSolver::CellFields &fields,
                   const unsigned int                      step,
                   const double                            t,
                   const bool                              last)
  {
    if (!writes(last))
      return;

    DataOut<3>     data_out;
    Vector<double> material_id;
    add_displacement_and_materials(data_out,
                                   discretization.dof_handler,
                                   u,
                                   material_id);
    data_out.add_data_vector(fields.J, "J");
    data_out.add_data_vector(fields.von_mises, "von_Mises_stress");
    data_out.add_data_vector(fields.strain, "principal_strain");
    data_out.build_patches(discretization.mapping, discretization.fe.degree);

    const std::string name =
      basename + "-" + Utilities::int_to_string(step, 4) + ".vtu";
    write_vtu_file(data_out, directory + "/" + name);
    records.emplace_back(t, name);
    // deal.II stamps the record with the date and time, which has no
    // flag to turn it off: the line is dropped, so that two runs of the
    // same input write the same bytes.
    std::ostringstream record;
    DataOutBase::write_pvd_record(record, records);
    std::istringstream lines(record.str());
    const std::string  pvd_file = directory + "/" + basename + ".pvd";
    ResultFile         pvd(pvd_file, "Output/Output directory");
    for (std::string line; std::getline(lines, line);)
      if (line.rfind("#This file was generated", 0) != 0)
        pvd.stream() << line << '\n';
    pvd.commit();
  }
} // namespace ddfem::report
