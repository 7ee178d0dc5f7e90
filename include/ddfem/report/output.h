#ifndef ddfem_report_output_h
#define ddfem_report_output_h

#include <deal.II/base/parameter_handler.h>
#include <deal.II/lac/vector.h>
#include <deal.II/numerics/data_out.h>

#include <ddfem/solver/discretization.h>
#include <ddfem/solver/static_solver.h>

#include <string>
#include <utility>
#include <vector>

namespace ddfem::report
{
  using namespace dealii;

  /**
   * Runs gnuplot on the script @p script in @p directory (where the script
   * reads and writes its files), without a shell. Throws ExcMessage naming
   * the script if gnuplot fails, after removing the @p images it draws
   * (names in @p directory), which it may have left half written; and
   * naming the Debian package if it cannot be started.
   */
  void
  run_gnuplot(const std::string              &directory,
              const std::string              &script,
              const std::vector<std::string> &images);

  /**
   * Throws ExcMessage naming the Debian package unless gnuplot starts and
   * draws with its pngcairo terminal: for a check before a run of the run
   * type @p run_type ("compare", "dg convergence"), whose plots come last.
   */
  void
  check_gnuplot(const std::string &run_type);

  /**
   * @p text as a gnuplot single-quoted string: quotes doubled, so no text
   * (a scene name, say) can end the string or reach gnuplot's command
   * substitution.
   */
  std::string
  gnuplot_string(const std::string &text);

  /**
   * The gnuplot point type and colour ("pt 7 lc rgb '#D55E00'") of the
   * @p series-th series of a plot: eight filled or distinct markers in
   * colours that stay apart for colour-blind readers (the seven of Okabe
   * and Ito's palette other than its yellow, which is unreadable on white,
   * and grey), repeated after eight. Each plot gives the same series (the same
   * method) the same style.
   */
  std::string
  gnuplot_style(unsigned int series);

  /**
   * Attaches @p dof_handler to @p data_out with the displacement @p u
   * (three components, one vector field) and the cells' material ids,
   * which it writes into @p material_id: that vector must live until the
   * patches are built. The CG and DG writers add their own fields.
   */
  void
  add_displacement_and_materials(DataOut<3>           &data_out,
                                 const DoFHandler<3>  &dof_handler,
                                 const Vector<double> &u,
                                 Vector<double>       &material_id);

  /**
   * Writes the patches of @p data_out to the VTU file @p file, without
   * the date and time deal.II would put in its header, so that two runs
   * of the same input write the same bytes. Throws ExcMessage naming
   * @p file and Output/Output directory if it cannot be written.
   */
  void
  write_vtu_file(DataOut<3> &data_out, const std::string &file);

  /**
   * Writes the states of a solve as VTU files, one per load step, and a
   * .pvd record over them: displacement, material id, det F and the von
   * Mises Cauchy stress (averaged over each cell's quadrature points with
   * the rule's weights) and the largest principal strain
   * (each cell's largest material::principal_strain, max_i |lambda_i - 1|,
   * which is positive under compression too). Declared in the prm subsection
   * "Output" next to the output directory.
   */
  class VtuWriter
  {
  public:
    /// Declares "Output/Write VTU".
    static void
    declare_parameters(ParameterHandler &prm);

    /// Reads "Output/Write VTU".
    void
    parse_parameters(ParameterHandler &prm);

    /**
     * Prepares to write the files of scene state @p state (0: before any
     * material edit, k: after edit k) into @p directory: NAME-<step>.vtu
     * and NAME.pvd, where NAME is "solution" for state 0 and "edit-k"
     * after edit k.
     */
    void
    initialize(const std::string &directory, const unsigned int state);

    /**
     * Throws ExcMessage naming Output/Output directory if write() could not
     * write the files of the scene states 0 to @p n_states - 1 into
     * @p directory (if it exists), or remove_earlier() could not remove an
     * earlier run's VTU files there: something other than a regular file is
     * in the way of a state's NAME.pvd or of an earlier VTU file, or it
     * cannot be removed. For the checks before a solve.
     */
    void
    check_writable(const std::string &directory,
                   const unsigned int n_states) const;

    /**
     * Removes the VTU files an earlier run left in @p directory, of every
     * scene state (NAME.pvd, NAME.vtu and every NAME-<step>.vtu, NAME
     * "solution" or "edit-<k>", and their ResultFile temporaries that a
     * killed run left), whether or not this run writes any: no
     * earlier run's result, another model's (a DG run writes NAME.vtu) or
     * a state this run does not have (a run with fewer edits), may be taken
     * for this run's. After check_writable(), before the first result is
     * written.
     */
    static void
    remove_earlier(const std::string &directory);

    /**
     * Whether a file named @p name (no directory) is one that write()
     * writes or remove_earlier() removes: NAME.pvd, NAME.vtu or
     * NAME-<step>.vtu of a scene state NAME, or the temporary of one.
     */
    static bool
    is_vtu_file(const std::string &name);

    /**
     * Writes the state @p u with @p fields at load step @p step and load
     * factor @p t, if the "Write VTU" setting asks for it (@p last tells
     * whether this is the final state).
     */
    void
    write(const solver::Discretization           &discretization,
          const Vector<double>                   &u,
          const solver::StaticSolver::CellFields &fields,
          const unsigned int                      step,
          const double                            t,
          const bool                              last);

    /// Whether any file is written ('Write VTU' is not 'none').
    bool
    enabled() const
    {
      return when != "none";
    }

    /// Whether write() writes the state of a load step (@p last: the
    /// final state).
    bool
    writes(const bool last) const
    {
      return when == "every step" || (when == "last step" && last);
    }

  private:
    /// 'Write VTU': every step, last step or none.
    std::string when;
    /// "solution" for scene state 0, "edit-k" after material edit k.
    static std::string
    state_name(const unsigned int state);

    /// The VTU files of any scene state in @p directory that an earlier run
    /// may have written (see remove_earlier()), sorted. Throws if
    /// @p directory exists and cannot be listed.
    static std::vector<std::string>
    existing_files(const std::string &directory);

    /// Where and under which name files are written.
    std::string directory, basename;
    /// (load factor, file name) of every file written, for the .pvd record.
    std::vector<std::pair<double, std::string>> records;
  };
} // namespace ddfem::report

#endif
