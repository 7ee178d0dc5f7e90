#include <deal.II/base/conditional_ostream.h>
#include <deal.II/base/mpi.h>
#include <deal.II/base/timer.h>
#include <deal.II/base/utilities.h>

#include <boost/io/ios_state.hpp>
#include <ddfem/app/application.h>
#include <ddfem/app/comparison.h>
#include <ddfem/app/model_run.h>
#include <ddfem/base/exceptions.h>
#include <ddfem/base/files.h>
#include <ddfem/base/parsing.h>
#include <ddfem/coarsening/builder.h>
#include <ddfem/dg/parameters.h>
#include <ddfem/dg/scene_solver.h>
#include <ddfem/dg/studies.h>
#include <ddfem/report/output.h>
#include <ddfem/scene/scene.h>
#include <ddfem/solver/discretization.h>
#include <ddfem/solver/linear_solver.h>
#include <ddfem/solver/static_solver.h>
#include <ddfem/solver/supports.h>
#include <nlohmann/json.hpp>

#include <algorithm>
#include <cctype>
#include <filesystem>
#include <fstream>
#include <functional>
#include <iomanip>
#include <new>
#include <optional>
#include <sstream>
#include <string_view>

namespace ddfem::app
{
  namespace
  {
    const char *usage =
      "Usage: ddfem PRM [--set \"Subsection/Name=value\"]...\n"
      "       ddfem --print-parameters\n"
      "       ddfem --help\n"
      "\n"
      "Runs the scene described by the deal.II parameter file PRM and writes\n"
      "summary.json, VTU files and the parameters used into its\n"
      "'Output/Output directory'. --set overrides any parameter (repeatable);\n"
      "nested subsections are separated by '/'. --print-parameters lists\n"
      "every parameter with its documentation and default.\n";

    /// The two hexadecimal digits of the byte @p c ("1b").
    std::string
    hex_digits(const char c)
    {
      std::ostringstream code;
      code << std::hex << std::setw(2) << std::setfill('0')
           << int(static_cast<unsigned char>(c));
      return code.str();
    }

    /// The length in bytes of the control character that @p text starts
    /// with: 1 for an ASCII one, 2 for a C1 control in UTF-8 (U+0080 to
    /// U+009F, bytes C2 80 to C2 9F; a terminal may take U+009B as it
    /// takes ESC '['), 0 if @p text starts with none.
    std::size_t
    control_character_length(const std::string_view text)
    {
      if (text.empty())
        return 0;
      if (std::iscntrl(static_cast<unsigned char>(text[0])))
        return 1;
      const auto second =
        text.size() > 1 ? static_cast<unsigned char>(text[1]) : 0;
      return static_cast<unsigned char>(text[0]) == 0xc2 && second >= 0x80 &&
                 second <= 0x9f ?
               2 :
               0;
    }

    /// How a message shows the control character at the start of
    /// @p text, of control_character_length() @p length: "0x1b" or
    /// "U+009B".
    std::string
    control_character_name(const std::string_view text,
                           const std::size_t      length)
    {
      if (length == 1)
        return "0x" + hex_digits(text[0]);
      std::string digits = hex_digits(text[1]);
      std::transform(digits.begin(), digits.end(), digits.begin(), ::toupper);
      return "U+00" + digits;
    }

    /// The first control character of @p text that is not one of
    /// @p allowed, as control_character_name() shows it, or "" if it has
    /// none.
    std::string
    first_control_character(const std::string_view text,
                            const std::string_view allowed)
    {
      for (std::size_t i = 0; i < text.size(); ++i)
        if (const std::size_t length = control_character_length(text.substr(i));
            length > 0 && allowed.find(text[i]) == std::string_view::npos)
          return control_character_name(text.substr(i), length);
      return "";
    }

    /// @p text with each control character other than a line break or a
    /// tab written as "\xHH" (or "\u00HH" for a C1 control): an error
    /// message may echo a file name the user typed, and a terminal takes
    /// an escape character as a command.
    std::string
    printable(const std::string &text)
    {
      std::string result;
      for (std::size_t i = 0; i < text.size();)
        {
          const std::size_t length =
            control_character_length(std::string_view(text).substr(i));
          if (length == 0 || text[i] == '\n' || text[i] == '\t')
            result += text[i++];
          else
            {
              result += (length == 1 ? "\\x" : "\\u00") +
                        hex_digits(text[i + length - 1]);
              i += length;
            }
        }
      return result;
    }

    /// Why a parameter file cannot hold @p value, as the end of a sentence
    /// ("holds '#'"), or "" if it can: a line break ends the line, '#'
    /// starts a comment, ParameterHandler reads a tab as a space, a final
    /// '\' continues the line, a control character is refused, and white
    /// space at either end is trimmed.
    std::string
    parameter_file_misfit(const std::string &value)
    {
      if (value.find_first_of("\n\r") != std::string::npos)
        return "holds a line break";
      if (value.find('#') != std::string::npos)
        return "holds '#'";
      if (value.find('\t') != std::string::npos)
        return "holds a tab";
      if (const std::string control = first_control_character(value, "");
          !control.empty())
        return "holds the control character " + control;
      if (!value.empty() && value.back() == '\\')
        return "ends in '\\'";
      if (value != Utilities::trim(value))
        return "starts or ends with white space";
      return "";
    }



    /**
     * The scene's name: 'Scene name', or the stem of @p prm_file, which then
     * becomes 'Scene name' in @p prm, so that a rerun from the run's
     * parameters.prm keeps it. Throws ExcMessage if it is not UTF-8 text,
     * which the JSON results need, or holds a control character, or is a
     * stem that a parameter file cannot hold (parameter_file_misfit()).
     */
    std::string
    scene_name_of(ParameterHandler &prm, const std::string &prm_file)
    {
      const std::string given = prm.get("Scene name");
      const std::string name =
        given.empty() ? std::filesystem::path(prm_file).stem().string() : given;
      try
        {
          nlohmann::json(name).dump();
        }
      catch (const nlohmann::json::type_error &)
        {
          AssertThrow(false,
                      ExcMessage(std::string("The scene name (") +
                                 (given.empty() ?
                                    "the parameter file's name; 'Scene name' "
                                    "is empty" :
                                    "'Scene name'") +
                                 ") is not UTF-8 text, which summary.json "
                                 "and comparison.json need. Set 'Scene "
                                 "name' to UTF-8 text."));
        }
      // The name is printed: the terminal would take a control character
      // as a command, and a carriage return would overwrite the line. Only
      // a file name can hold one ('Scene name' is checked as every value
      // is, and a parameter file's line holds no line break).
      const std::string control = first_control_character(name, "");
      AssertThrow(control.empty(),
                  ExcMessage("The parameter file's name, the scene's name "
                             "while 'Scene name' is empty, holds the control "
                             "character " +
                             control +
                             ". Set 'Scene name', or rename the file."));
      if (given.empty())
        {
          const std::string misfit = parameter_file_misfit(name);
          AssertThrow(misfit.empty(),
                      ExcMessage("The parameter file's name, the scene's "
                                 "name while 'Scene name' is empty, " +
                                 misfit +
                                 ", which the run's parameters.prm could not "
                                 "hold (a rerun from it would take another "
                                 "name). Set 'Scene name', or rename the "
                                 "file."));
          prm.set("Scene name", name);
        }
      return name;
    }

    /**
     * Throws ExcMessage naming the parameter and @p prm_file if a value of
     * @p prm cannot be held by a parameter file (parameter_file_misfit()):
     * only an XML or JSON file can give one (call it for those), and the
     * run's parameters.prm would not repeat it.
     */
    void
    check_values_fit(const ParameterHandler &prm, const std::string &prm_file)
    {
      std::ostringstream text;
      prm.print_parameters(text, ParameterHandler::ShortJSON);
      const std::function<void(const nlohmann::json &, const std::string &)>
        check = [&](const nlohmann::json &node, const std::string &path) {
          for (const auto &[name, value] : node.items())
            if (value.is_object())
              check(value, path + name + "/");
            else
              {
                const std::string text =
                  value.is_string() ? value.get<std::string>() : "";
                const std::string misfit = parameter_file_misfit(text);
                AssertThrow(misfit.empty(),
                            ExcMessage("In parameter file \"" + prm_file +
                                       "\": " + path + name + " " + misfit +
                                       ", which the run's parameters.prm "
                                       "could not hold (a rerun from it would "
                                       "read another value)."));
              }
        };
      nlohmann::json values;
      try
        {
          values = nlohmann::json::parse(text.str());
        }
      catch (const nlohmann::json::exception &)
        {
          AssertThrow(false,
                      ExcMessage("In parameter file \"" + prm_file +
                                 "\": a value is not UTF-8 text."));
        }
      check(values, "");
    }

    /// 'Output directory' and 'Screen timings' of subsection "Output".
    struct OutputSettings
    {
      /// Reads them from @p prm.
      explicit OutputSettings(ParameterHandler &prm)
      {
        prm.enter_subsection("Output");
        directory      = prm.get("Output directory");
        screen_timings = prm.get_bool("Screen timings");
        prm.leave_subsection();
      }

      /// Where a run writes its files.
      std::string directory;
      /// Whether per-phase times are printed on the screen.
      bool screen_timings;
    };

    /**
     * The end of a message on an undeclared subsection or parameter: where
     * the declared names are listed. If the undeclared subsection
     * (@p missing_subsection) is a numbered boundary condition, the last
     * component of @p path ("Boundary conditions/Condition 9", or with '.'
     * as deal.II writes it), also how many there are.
     */
    std::string
    declared_names_hint(const bool missing_subsection, const std::string &path)
    {
      std::string       hint = " (a run's parameters.prm and 'ddfem "
                               "--print-parameters' list them all";
      const std::size_t last = path.find_last_of("/.");
      const std::string parent =
        last == std::string::npos ? std::string() : path.substr(0, last);
      const std::string condition = "Condition ", group = "Boundary conditions";
      if (missing_subsection && last != std::string::npos &&
          path.compare(last + 1, condition.size(), condition) == 0 &&
          parent.size() >= group.size() &&
          parent.compare(parent.size() - group.size(), group.size(), group) ==
            0)
        hint += "; Boundary conditions has the subsections Condition 1 to "
                "Condition " +
                std::to_string(scene::BoundaryConditions::max_conditions);
      return hint + ").";
    }

    /// Applies "Subsection/.../Name=value" to @p prm.
    void
    apply_override(ParameterHandler &prm, const std::string &text)
    {
      const auto equal = text.find('=');
      // First, as no message may echo it: the terminal would take it as a
      // command. The parameter is named where its name has none.
      const std::string control = first_control_character(text, "\t\n\r");
      const std::string shown =
        first_control_character(text.substr(0, equal), "\t\n\r").empty() ?
          text.substr(0, equal) + "=..." :
          "...";
      AssertThrow(control.empty(),
                  ExcMessage("--set \"" + shown +
                             "\": it holds the control character " + control +
                             ", which a parameter file cannot hold."));
      AssertThrow(equal != std::string::npos,
                  ExcMessage("--set \"" + text +
                             "\": expected \"Subsection/Name=value\"."));
      const auto path =
        split_list(text.substr(0, equal), '/', "--set \"" + text + "\"");
      const auto value = Utilities::trim(text.substr(equal + 1));
      AssertThrow(!path.empty(),
                  ExcMessage("--set \"" + text + "\": no parameter name."));
      // The run's parameters.prm could not be read back: a parameter file
      // has no way to write these in a value ('#' starts a comment, a '\'
      // at the end continues the line).
      AssertThrow(text.find_first_of("\n\r") == std::string::npos,
                  ExcMessage("--set \"" + text +
                             "\": a value must not contain a line break."));
      const std::string misfit = parameter_file_misfit(value);
      AssertThrow(misfit.empty(),
                  ExcMessage("--set \"" + text + "\": the value " + misfit +
                             ", which a parameter file cannot hold."));
      // A misspelt subsection or parameter is named as such (deal.II would
      // create the misspelt subsection and then report a missing entry).
      const std::string name     = text.substr(0, equal);
      const std::string sections = name.substr(0, name.rfind('/'));
      AssertThrow(path.size() == 1 ||
                    prm.subsection_path_exists({path.begin(), path.end() - 1}),
                  ExcMessage("--set \"" + text +
                             "\": there is no subsection \"" + sections + "\"" +
                             declared_names_hint(true, sections)));
      for (unsigned int i = 0; i + 1 < path.size(); ++i)
        prm.enter_subsection(path[i]);
      try
        {
          prm.set(path.back(), value);
        }
      catch (const ParameterHandler::ExcEntryUndeclared &)
        {
          AssertThrow(false,
                      ExcMessage("--set \"" + text +
                                 "\": there is no parameter \"" + path.back() +
                                 "\"" +
                                 (path.size() == 1 ?
                                    std::string(" outside the subsections") :
                                    " in subsection \"" + sections + "\"") +
                                 declared_names_hint(false, sections)));
        }
      catch (ExceptionBase &e)
        {
          AssertThrow(false,
                      ExcMessage("--set \"" + text + "\": " + message_of(e)));
        }
      for (unsigned int i = 0; i + 1 < path.size(); ++i)
        prm.leave_subsection();
    }

    /**
     * Prints the displacements at the @p probes (in mm, 5 digits: parts
     * are centimetres in size).
     */
    void
    print_probes(const std::vector<Probe> &probes,
                 const ConditionalOStream &pcout)
    {
      for (const auto &[x, u] : probes)
        {
          std::ostringstream line;
          line << "  probe (" << x << " m): u = (" << std::setprecision(5)
               << 1e3 * u << ") mm";
          pcout << line.str() << std::endl;
        }
    }

    /**
     * Throws before anything is solved or written if a result could not
     * be written into the output directory @p directory: it cannot be
     * created, or something other than a regular file is in the way of
     * summary.json, parameters.prm or the VTU files (written by @p vtu) of
     * @p n_states scene states (0: a DG run's solution.vtu only), or of an
     * earlier run's results that write_output() removes, or
     * @p database_file (empty: none) is one of these
     * (check_earlier_results()).
     */
    void
    check_output(const std::string       &directory,
                 const report::VtuWriter &vtu,
                 const unsigned int       n_states,
                 const std::string       &database_file)
    {
      check_writable_in(directory,
                        {"parameters.prm"},
                        "Output/Output directory");
      check_earlier_results(directory, vtu, database_file);
      vtu.check_writable(directory, n_states);
    }

    /**
     * Creates the output directory @p directory, removes the results an
     * earlier run left there (remove_earlier_results()), writes @p prm as
     * parameters.prm and runs @p write_results, which writes this run's
     * results (all after check_output()); returns what @p write_results
     * returns. If anything throws, what was written is removed again,
     * parameters.prm and the directories made for it included: a failed
     * run leaves nothing of its own (a run that is killed leaves the
     * parameters of what it wrote). A run started from that parameters.prm
     * (one of its @p inputs, the parameter file and the files it includes)
     * puts it back as it was instead: it is the run's input.
     */
    int
    write_output(const std::string              &directory,
                 const std::vector<std::string> &inputs,
                 const ParameterHandler         &prm,
                 const std::function<int()>     &write_results)
    {
      const std::string          used_file = directory + "/parameters.prm";
      std::error_code            error;
      std::optional<std::string> input;
      if (is_input_file(used_file, inputs))
        {
          std::ifstream      file(used_file, std::ios::binary);
          std::ostringstream bytes;
          bytes << file.rdbuf();
          AssertThrow(file.good() || file.eof(),
                      ExcMessage("Cannot read \"" + used_file +
                                 "\", the parameter file of this run, "
                                 "before replacing it."));
          input = bytes.str();
        }
      const auto made =
        create_directories(directory, "Output/Output directory");
      remove_earlier_results(directory);
      try
        {
          ResultFile used(used_file, "Output/Output directory");
          prm.print_parameters(used.stream(), ParameterHandler::ShortPRM);
          used.commit();
          return write_results();
        }
      catch (...)
        {
          // Best effort: the error to report is the first one. This run's
          // parameters.prm goes before the directories made for it are
          // removed where empty; where it replaced the run's input, the
          // input goes back, after the results, whose space it may need,
          // in one rename: if that fails, the file keeps this run's
          // parameters rather than nothing.
          if (!input)
            std::filesystem::remove(used_file, error);
          remove_failed_results(directory, made);
          if (input)
            try
              {
                ResultFile restored(used_file, "Output/Output directory");
                restored.stream() << *input;
                restored.commit();
              }
            catch (...)
              {}
          throw;
        }
    }



    /**
     * One simulation of a scene with a continuous method (fine, ddfem,
     * naive or average) or the DG method: builds the discretization,
     * solves, writes VTU and summary.json.
     */
    class Simulation
    {
    public:
      Simulation(std::ostream &out, std::ostream &err)
        : pcout(out)
        , err(err)
      {}

      /**
       * Reads the run's settings from @p prm, read from @p prm_file, which
       * with the files it includes are @p input_files (resolved_path()).
       */
      void
      parse_parameters(ParameterHandler               &prm,
                       const std::string              &prm_file,
                       const std::vector<std::string> &input_files)
      {
        inputs     = input_files;
        scene_name = scene_name_of(prm, prm_file);
        method     = prm.get("Method");
        level      = prm.get_integer("Coarsening levels");
        prm.enter_subsection("Discretization");
        degree = prm.get_integer("Polynomial degree");
        prm.leave_subsection();
        const OutputSettings output(prm);
        directory      = output.directory;
        screen_timings = output.screen_timings;
        solver_parameters.parse_parameters(prm);
        linear_solver.parse_parameters(prm);
        vtu.parse_parameters(prm);
        // Each method reads only its own settings: DG the DG subsection,
        // coarse models the database and coarse point settings.
        if (method == "dg")
          dg_parameters.parse_parameters(prm);
        else if (method != "fine")
          database.parse_parameters(prm);
        scene.parse_parameters(prm);
        if (method != "dg")
          scene.palette.require_nonnegative_lambda("Method = " + method);
        if (method == "ddfem")
          database.check_simulation_input(scene.palette, level);
        AssertThrow(method != "dg" || scene.n_edits() == 0,
                    ExcMessage("Layout/Edits is not supported with Method = "
                               "dg (a DG run solves the base state only): "
                               "remove the edits or use another Method."));
      }

      int
      run(const ParameterHandler &prm)
      {
        return method == "dg" ? run_dg(prm) : run_continuous(prm);
      }

    private:
      /// Writes @p summary as summary.json.
      void
      write_summary(const nlohmann::json &summary) const
      {
        ResultFile json(directory + "/summary.json", "Output/Output directory");
        json.stream() << summary.dump(2) << std::endl;
        json.commit();
      }

      /// The DG method: linear or corotated elasticity, one solve.
      int
      run_dg(const ParameterHandler &prm)
      {
        Timer total;
        // Before the setup, whose penalty check costs most of the solve.
        check_output(directory, vtu, 0, "");
        dg::SceneSolver solver(scene, dg_parameters, linear_solver);
        solver.setup();
        const auto &n      = scene.grid.size();
        const auto &system = solver.system();
        pcout << "Scene \"" << scene_name << "\", method dg\n"
              << "  grid " << scene.grid.describe() << "\n"
              << "  " << system.dof_handler.get_triangulation().n_active_cells()
              << " cells, " << system.dof_handler.n_dofs() << " DoFs ("
              << dg_parameters.element_name() << "(" << dg_parameters.degree
              << ")^3), flux " << dg_parameters.flux_name() << ", "
              << system.matrix.n_nonzero_elements() << " nonzeros, linear "
              << "solver " << solver.linear_solver_name() << "\n"
              << "  penalty eta = " << system.penalty()
              << (dg_parameters.automatic_penalty() ?
                    " (automatic, " + std::to_string(system.penalty_doublings) +
                      " doublings)" :
                    std::string(" (fixed)"))
              << ", K " << dg::to_string(solver.definiteness) << std::endl;
        for (const Point<3> &p : scene.probes)
          solver.point_value(p); // throws if outside

        // All input is valid. One solve, then the results are written (a
        // corotated iteration that does not converge writes nothing).
        // Every VTU file of an earlier run is removed, solution.vtu with
        // them (a DG run writes no continuous states).
        const unsigned int solves = solver.solve();
        return write_output(directory, inputs, prm, [&]() {
          if (vtu.enabled())
            solver.write_vtu(directory + "/solution.vtu");

          nlohmann::json summary;
          summary["scene"]        = scene_name;
          summary["grid"]         = {n[0], n[1], n[2]};
          summary["voxel_size"]   = scene.grid.voxel_size();
          summary["solid_voxels"] = scene.grid.n_solid_voxels();
          solver.summarize(summary);
          pcout << "Solved with " << solves << " linear solve"
                << (solves == 1 ? "" : "s") << std::endl;
          std::vector<Probe> probes;
          for (const Point<3> &p : scene.probes)
            probes.push_back({p, solver.point_value(p)});
          print_probes(probes, pcout);
          summary["probes"]         = to_json(probes);
          summary["wall_time_s"]    = total.wall_time();
          summary["peak_memory_mb"] = peak_memory_mb();
          write_summary(summary);
          // The times of summary.json: the solve time covers every solve of a
          // corotated run (and its assemblies); the integration and assembly
          // times are those of the last assembly.
          if (screen_timings)
            pcout << std::setprecision(4) << "  wall time "
                  << summary["wall_time_s"].get<double>() << " s, setup "
                  << summary["time_setup_s"].get<double>() << " s, solve "
                  << summary["time_solve_s"].get<double>()
                  << " s; last assembly: integration "
                  << summary["time_integration_s"].get<double>()
                  << " s, adding into K and F "
                  << summary["time_assembly_s"].get<double>()
                  << " s\n  peak memory "
                  << summary["peak_memory_mb"].get<double>() << " MiB"
                  << std::endl;
          return 0;
        });
      }

      /**
       * The continuous Neo-Hookean models: fine, or coarse (ddfem, naive,
       * average) at 'Coarsening levels'; then each material edit.
       */
      int
      run_continuous(const ParameterHandler &prm)
      {
        Timer total;
        // Files that could not be written are found before a database
        // preparation or a solve.
        check_output(directory,
                     vtu,
                     scene.n_edits() + 1,
                     method == "ddfem" ? database.file() : "");
        // The coarse material source: the database (completed lazily for
        // this scene's blocks, in every edited state) or a baseline.
        std::optional<coarsening::Database>    level1;
        coarsening::Hierarchy                  level2;
        std::unique_ptr<coarsening::Coarsener> coarsener;
        double                                 database_time = 0;
        if (method != "fine")
          {
            // The scene must be one the fine model accepts: conditions on
            // the solid, voxels supported as they are, not only through
            // blocks that bridge a gap between them.
            solver::check_voxel_scene(scene);
            if (method == "ddfem")
              {
                // The rest of the input is checked before any fitting.
                check_coarse_model(scene,
                                   degree,
                                   level,
                                   database.point_offset(level),
                                   solver_parameters,
                                   linear_solver);
                Timer preparation;
                level1.emplace(database.prepare(scene.palette,
                                                scene.states(),
                                                level,
                                                level2,
                                                pcout.get_stream()));
                database_time = preparation.wall_time();
              }
            coarsener = std::make_unique<coarsening::Coarsener>(
              coarsening::coarsening_method(method),
              level,
              scene.palette,
              database.point_offset(level),
              level1 ? &*level1 : nullptr,
              &level2);
          }

        ModelRun    run(scene,
                     degree,
                     coarsener.get(),
                     solver_parameters,
                     linear_solver,
                     pcout);
        const auto &n     = scene.grid.size();
        const auto &model = run.discretization();
        pcout << "Scene \"" << scene_name << "\", method " << method;
        if (coarsener)
          pcout << ", coarsening level " << level;
        pcout << "\n"
              << "  grid " << scene.grid.describe() << "\n"
              << "  " << model.triangulation.n_active_cells() << " cells";
        if (coarsener)
          pcout << " (blocks of " << (1u << level) << "^3 voxels, "
                << model.quadrature.size() << " quadrature points each)";
        pcout << ", " << model.dof_handler.n_dofs() << " DoFs (FE_Q("
              << model.fe.degree << ")^3), linear solver "
              << linear_solver.method() << std::endl;

        // All input is valid: from here on, results are written.
        return write_output(directory, inputs, prm, [&]() {
          nlohmann::json summary;
          summary["scene"]           = scene_name;
          summary["method"]          = method;
          summary["level"]           = coarsener ? level : 0;
          summary["grid"]            = {n[0], n[1], n[2]};
          summary["voxel_size"]      = scene.grid.voxel_size();
          summary["solid_voxels"]    = scene.grid.n_solid_voxels();
          summary["cells"]           = model.triangulation.n_active_cells();
          summary["dofs"]            = model.dof_handler.n_dofs();
          summary["degree"]          = model.fe.degree;
          summary["linear_solver"]   = linear_solver.method();
          summary["database_time_s"] = database_time;
          summary["edits"]           = nlohmann::json::array();

          bool converged = true;
          for (unsigned int state = 0; state <= scene.n_edits(); ++state)
            {
              if (state > 0)
                {
                  const auto changed = scene.apply_edit(state - 1);
                  run.edit(changed);
                  pcout << "Edit " << state << ": " << changed.size()
                        << " voxels change material" << std::endl;
                }
              vtu.initialize(directory, state);
              const ModelRun::Result result = run.solve(&vtu);
              converged              = converged && result.statistics.converged;
              const auto &statistics = result.statistics;
              pcout << (statistics.converged ? "Converged " : "NOT converged ")
                    << statistics.describe() << "\n"
                    << "  min J = " << std::setprecision(4) << result.min_J
                    << " at the quadrature points, " << statistics.min_vertex_J
                    << " at the vertices, max |u| = " << result.max_displacement
                    << " m\n"
                    << "  principal strain per cell: median "
                    << result.strain_quantiles[0] << ", 99 % "
                    << result.strain_quantiles[1] << ", max "
                    << result.strain_quantiles[2] << std::endl;
              // An edit updates only the cells (coarse blocks) it touches.
              if (state > 0)
                pcout << "  new materials in " << result.cells_updated << " of "
                      << model.triangulation.n_active_cells() << " cells"
                      << std::endl;
              print_probes(result.probes, pcout);
              const nlohmann::json json = result.to_json();
              if (state == 0)
                summary.update(json);
              else
                summary["edits"].push_back(json);
              if (screen_timings)
                {
                  pcout << "  wall time " << result.wall_time << " s";
                  for (const auto &[section, seconds] : result.phases)
                    pcout << ", " << section << " " << seconds << " s";
                  pcout << std::endl;
                }
              if (!statistics.converged)
                err << "Error: the solve did not converge: "
                    << statistics.failure << "." << std::endl;
            }
          summary["total_wall_time_s"] = total.wall_time();
          const double peak_memory     = peak_memory_mb();
          summary["peak_memory_mb"]    = peak_memory;
          write_summary(summary);
          if (screen_timings)
            pcout << "  peak memory " << peak_memory << " MiB" << std::endl;
          return converged ? 0 : 1;
        });
      }

      ConditionalOStream pcout;
      std::ostream      &err;
      /// The parameter file and the files it includes (resolved_path()).
      std::vector<std::string>         inputs;
      std::string                      scene_name, method, directory;
      unsigned int                     degree, level;
      bool                             screen_timings;
      scene::Scene                     scene;
      solver::StaticSolver::Parameters solver_parameters;
      solver::LinearSolver             linear_solver;
      report::VtuWriter                vtu;
      dg::Parameters                   dg_parameters;
      coarsening::DatabaseBuilder      database;
    };
  } // namespace



  namespace
  {
    /**
     * Run type "database": fits the metamaterials of the scene's palette
     * (all combinations, or only those of the scene's blocks in every state,
     * its material edits included, as a simulation of the scene needs them)
     * into the database file.
     */
    int
    build_database(ParameterHandler &prm, std::ostream &out)
    {
      scene::Scene scene;
      scene.parse_parameters(prm);
      coarsening::DatabaseBuilder builder;
      builder.parse_parameters(prm);
      const OutputSettings output(prm);
      const bool           all =
        builder.scope() == coarsening::DatabaseBuilder::Scope::all;
      const std::vector<scene::VoxelGrid> grids =
        all ? std::vector<scene::VoxelGrid>() : scene.states();
      builder.check_scene(scene.palette, grids);

      const auto            held = builder.lock(scene.palette, out);
      coarsening::Hierarchy level2;
      coarsening::Database  database = builder.open(scene.palette, level2, out);
      builder.build(scene.palette,
                    database,
                    level2,
                    all ? nullptr : &grids,
                    out,
                    output.screen_timings);
      return 0;
    }



    /**
     * Run types "dg convergence" and "dg cost": the DG studies of
     * subsections "DG convergence" and "DG cost" (the scene is ignored),
     * read from the parameter file and the files it includes, @p inputs.
     * Checks the study's settings and its output (check_output()) before it
     * writes its results as a simulation does (write_output()).
     */
    int
    run_dg_study(const std::string              &run_type,
                 ParameterHandler               &prm,
                 const std::vector<std::string> &inputs,
                 std::ostream                   &out)
    {
      const OutputSettings output(prm);
      report::VtuWriter    vtu;
      vtu.parse_parameters(prm);
      const bool           convergence = (run_type == "dg convergence");
      dg::ConvergenceStudy convergence_study;
      dg::CostStudy        cost_study;
      if (convergence)
        {
          convergence_study.parse_parameters(prm);
          report::check_gnuplot("dg convergence");
        }
      else
        cost_study.parse_parameters(prm);
      check_output(output.directory, vtu, 0, "");
      return write_output(output.directory, inputs, prm, [&]() {
        if (convergence)
          convergence_study.run(output.directory, out);
        else
          cost_study.run(output.directory, output.screen_timings, out);
        return 0;
      });
    }
  } // namespace



  namespace
  {
    /**
     * Throws if the include statements of the parameter file @p file,
     * followed as ParameterHandler follows them (paths as written, from the
     * working directory; an included file is read as PRM text whatever its
     * name), lead back to a file of @p chain, the files that include it
     * (each as written and as resolved_path() gives it). ParameterHandler would
     * recurse until the stack overflows. A top-level XML or JSON file has
     * no include statements. Adds the resolved path of every file read to
     * @p read.
     */
    void
    check_include_cycles(
      const std::string                                &file,
      std::vector<std::pair<std::string, std::string>> &chain,
      std::vector<std::string>                         &read)
    {
      const std::string path = resolved_path(file).string();
      for (std::size_t i = 0; i < chain.size(); ++i)
        if (chain[i].second == path)
          {
            std::string cycle;
            for (std::size_t j = i; j < chain.size(); ++j)
              cycle += "\"" + chain[j].first + "\" includes ";
            AssertThrow(false,
                        ExcMessage("its include statements form a cycle: " +
                                   cycle + "\"" + file + "\" again."));
          }
      // ParameterHandler would read nothing from a directory, and forever
      // from /dev/zero; a named pipe would wait for a writer.
      const std::string kind = non_regular_kind(file);
      AssertThrow(chain.empty() || kind.empty(),
                  ExcMessage("\"" + chain.back().first + "\" includes \"" +
                             file + "\", which is " + kind + "."));
      std::ifstream input(file);
      if (!input)
        return; // ParameterHandler reports it
      read.push_back(path);
      if (chain.empty() && (lowercase_extension(file) == ".xml" ||
                            lowercase_extension(file) == ".json"))
        return;
      chain.emplace_back(file, path);
      // Statements as ParameterHandler reads them: lines trimmed, those
      // ending in '\' joined to the next (the last line too), white space
      // made spaces, without their comment; an include statement is
      // "include" or "INCLUDE" and a space before the file name.
      const auto check = [&](std::string statement) {
        std::replace_if(
          statement.begin(),
          statement.end(),
          [](const char c) {
            return std::isspace(static_cast<unsigned char>(c));
          },
          ' ');
        statement = Utilities::trim(statement.substr(0, statement.find('#')));
        if (statement.rfind("include ", 0) == 0 ||
            statement.rfind("INCLUDE ", 0) == 0)
          check_include_cycles(Utilities::trim(statement.substr(7)),
                               chain,
                               read);
      };
      std::string  line, statement;
      unsigned int number = 0;
      while (std::getline(input, line))
        {
          // ParameterHandler would echo a binary file's bytes in its
          // message (not those of a comment, which it drops).
          ++number;
          const std::string text    = line.substr(0, line.find('#'));
          const std::string control = first_control_character(text, "\t\r\v\f");
          AssertThrow(control.empty(),
                      ExcMessage("\"" + file + "\" is not a text file: line " +
                                 std::to_string(number) +
                                 " holds the control character " + control +
                                 "."));
          // ParameterHandler trims a line, but keeps a carriage return, a
          // vertical tab or a form feed inside a value, which the screen
          // would show by moving the cursor where the value is printed. A
          // line may end in a carriage return (Windows line ends) or hold
          // only a form feed (a page break).
          const std::string inside =
            first_control_character(Utilities::trim(text), "\t");
          AssertThrow(inside.empty(),
                      ExcMessage("\"" + file + "\": line " +
                                 std::to_string(number) +
                                 " holds the control character " + inside +
                                 " inside its text, where only spaces and "
                                 "tabs may stand."));
          line = Utilities::trim(line);
          if (!line.empty() && line.back() == '\\')
            {
              statement += line.substr(0, line.size() - 1);
              continue;
            }
          check(statement + line);
          statement.clear();
        }
      if (!statement.empty())
        check(statement);
      chain.pop_back();
    }



    /// Run type "compare": see Comparison.
    int
    run_comparison(ParameterHandler               &prm,
                   const std::string              &prm_file,
                   const std::vector<std::string> &input_files,
                   std::ostream                   &out,
                   std::ostream                   &err)
    {
      scene::Scene scene;
      scene.parse_parameters(prm);
      const OutputSettings output(prm);
      Comparison           comparison;
      comparison.parse_parameters(prm);
      // Written with the comparison's tables (Comparison::run()).
      check_writable_in(output.directory,
                        {"parameters.prm"},
                        "Output/Output directory");
      const int status = comparison.run(prm,
                                        scene,
                                        scene_name_of(prm, prm_file),
                                        output.directory,
                                        input_files,
                                        output.screen_timings,
                                        out);
      if (status != 0)
        err << "Error: a model of the comparison did not converge (NOT "
               "CONVERGED in the table); its errors and times are not "
               "meaningful."
            << std::endl;
      return status;
    }
  } // namespace



  void
  declare_parameters(ParameterHandler &prm)
  {
    prm.declare_entry(
      "Scene name",
      "",
      Patterns::Anything(),
      "Name of the scene in reports; empty means the parameter file's "
      "name without extension.");
    prm.declare_entry(
      "Run type",
      "simulation",
      Patterns::Selection("simulation|compare|database|dg convergence|dg cost"),
      "What to run: 'simulation' solves the scene with the 'Method'; "
      "'compare' solves it with the fine model and every coarse method and "
      "level of subsection 'Comparison' and reports error against run time; "
      "'database' builds (or extends, or resumes) the metamaterial database "
      "of the scene's palette described in subsection 'Database' and "
      "solves nothing; 'dg convergence' is the convergence study of "
      "subsection 'DG convergence' and 'dg cost' the cost comparison of "
      "subsection 'DG cost' (both ignore the scene).");
    prm.declare_entry(
      "Method",
      "fine",
      Patterns::Selection("fine|ddfem|naive|average|dg"),
      "Discretization: 'fine' is the continuous Neo-Hookean model on the "
      "voxel grid, one hexahedron per solid voxel. 'ddfem', 'naive' and "
      "'average' are coarse models, one trilinear hexahedron per block of "
      "2x2x2 (or 4x4x4, see 'Coarsening levels') voxels with a solid voxel, "
      "whose quadrature points get the block's metamaterial from the "
      "database of subsection 'Database' (fitted lazily if missing), the "
      "unfitted materials of the voxels they lie in, or the block's average "
      "material. 'dg' is discontinuous Galerkin linear (or corotated) "
      "elasticity on the voxel mesh, configured in subsection 'DG'.");
    prm.declare_entry(
      "Coarsening levels",
      "1",
      Patterns::Integer(1, 2),
      "Method = ddfem, naive or average: 1 for coarse elements of 2x2x2 "
      "voxels (8 quadrature points), 2 for 4x4x4 voxels (64 points).");
    prm.enter_subsection("Discretization");
    prm.declare_entry("Polynomial degree",
                      "1",
                      Patterns::Integer(1, 2),
                      "Degree p of the FE_Q(p)^3 displacement element, or k "
                      "of the DG element (Method = dg).");
    prm.leave_subsection();
    prm.enter_subsection("Output");
    prm.declare_entry(
      "Output directory",
      "output",
      Patterns::DirectoryName(),
      "Directory for summary.json, parameters.prm and VTU files; created "
      "if missing.");
    prm.declare_entry(
      "Screen timings",
      "true",
      Patterns::Bool(),
      "Print wall times and memory on screen. Tests switch this off to "
      "keep screen output deterministic (summary.json always has them).");
    prm.leave_subsection();
    report::VtuWriter::declare_parameters(prm);
    scene::Scene::declare_parameters(prm);
    solver::StaticSolver::Parameters::declare_parameters(prm);
    solver::LinearSolver::declare_parameters(prm);
    coarsening::DatabaseBuilder::declare_parameters(prm);
    Comparison::declare_parameters(prm);
    dg::Parameters::declare_parameters(prm);
    dg::ConvergenceStudy::declare_parameters(prm);
    dg::CostStudy::declare_parameters(prm);
  }



  int
  run(const std::vector<std::string> &arguments,
      std::ostream                   &out,
      std::ostream                   &err)
  {
    // A run may change the streams' precision; the caller's next run (tests
    // run several in one process) must print as if it were the first.
    const boost::io::ios_all_saver out_format(out), err_format(err);
    // Every MPI process would run the whole job and write the same output
    // and database files (or print the same usage).
    if (Utilities::MPI::job_supports_mpi() &&
        Utilities::MPI::n_mpi_processes(MPI_COMM_WORLD) > 1)
      {
        if (Utilities::MPI::this_mpi_process(MPI_COMM_WORLD) == 0)
          err << "Error: ddfem runs as one process and does its parallel "
                 "work with threads (assembly, and Database/Threads in "
                 "database builds), but it was started as "
              << Utilities::MPI::n_mpi_processes(MPI_COMM_WORLD)
              << " MPI processes, which would all write the same files. "
                 "Start it without mpirun."
              << std::endl;
        return 1;
      }
    if (arguments.empty() || arguments[0] == "--help" || arguments[0] == "-h")
      {
        if (arguments.size() > 1)
          err << "Error: " << arguments[0] << " takes no arguments.\n";
        (arguments.size() == 1 ? out : err) << usage;
        return arguments.size() == 1 ? 0 : 1;
      }
    try
      {
        ParameterHandler prm;
        declare_parameters(prm);
        if (arguments[0] == "--print-parameters")
          {
            AssertThrow(arguments.size() == 1,
                        ExcMessage("--print-parameters takes no arguments."));
            prm.print_parameters(out, ParameterHandler::PRM);
            return 0;
          }

        AssertThrow(arguments[0].rfind("-", 0) != 0,
                    ExcMessage("Unknown option \"" + arguments[0] +
                               "\": the parameter file comes first.\n" +
                               usage));
        const std::string prm_file = arguments[0];
        // (Checked before it is opened: a named pipe would wait there.)
        const std::string kind = non_regular_kind(prm_file);
        AssertThrow(kind.empty() && std::ifstream(prm_file).good(),
                    ExcMessage("Cannot read the parameter file \"" + prm_file +
                               "\"" +
                               (kind.empty() ? "." : ": it is " + kind + ".")));
        std::vector<std::string> input_files;
        try
          {
            std::vector<std::pair<std::string, std::string>> chain;
            check_include_cycles(prm_file, chain, input_files);
            prm.parse_input(prm_file);
          }
        catch (ExceptionBase &e)
          {
            std::string message = message_of(e);
            const bool  subsection =
              message.find("no such subsection") != std::string::npos;
            const bool undeclared =
              subsection ||
              message.find("No entry with name") != std::string::npos;
            if (undeclared && !message.empty() && message.back() == '.')
              message.pop_back();
            AssertThrow(false,
                        ExcMessage("In parameter file \"" + prm_file +
                                   "\": " + message +
                                   (undeclared ?
                                      declared_names_hint(subsection, message) :
                                      std::string())));
          }
        catch (std::exception &e) // the XML and JSON readers' errors
          {
            AssertThrow(false,
                        ExcMessage("In parameter file \"" + prm_file +
                                   "\": " + e.what()));
          }
        for (unsigned int i = 1; i < arguments.size(); ++i)
          {
            AssertThrow(arguments[i] != "--set" || i + 1 < arguments.size(),
                        ExcMessage(std::string("--set needs a value: --set "
                                               "\"Subsection/Parameter=value\"."
                                               "\n") +
                                   usage));
            AssertThrow(arguments[i] == "--set",
                        ExcMessage("Unexpected argument \"" + arguments[i] +
                                   "\".\n" + usage));
            apply_override(prm, arguments[++i]);
          }

        if (lowercase_extension(prm_file) == ".xml" ||
            lowercase_extension(prm_file) == ".json")
          check_values_fit(prm, prm_file);
        const std::string run_type = prm.get("Run type");
        if (run_type == "database")
          return build_database(prm, out);
        if (run_type == "dg convergence" || run_type == "dg cost")
          return run_dg_study(run_type, prm, input_files, out);
        if (run_type == "compare")
          return run_comparison(prm, prm_file, input_files, out, err);
        Simulation simulation(out, err);
        simulation.parse_parameters(prm, prm_file, input_files);
        return simulation.run(prm);
      }
    catch (ExceptionBase &e)
      {
        err << "Error: " << printable(message_of(e)) << std::endl;
      }
    catch (std::bad_alloc &)
      {
        err << "Error: out of memory. The run needs more memory than this "
               "machine has: make it smaller (Geometry/Grid size, a coarse "
               "method, or the refinements or resolution of a DG study)."
            << std::endl;
      }
    catch (std::exception &e)
      {
        err << "Error: " << printable(e.what()) << std::endl;
      }
    catch (...)
      {
        // A library may throw what is no std::exception (Epetra throws
        // ints): still an error message and exit code 1, not an abort.
        err << "Error: the run stopped with an exception of unknown type."
            << std::endl;
      }
    return 1;
  }
} // namespace ddfem::app
