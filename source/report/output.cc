#include <deal.II/base/data_out_base.h>
#include <deal.II/numerics/data_out.h>

#include <ddfem/report/output.h>

#include <cstdlib>
#include <fstream>

namespace ddfem::report
{
  void
  run_gnuplot(const std::string &directory, const std::string &script)
  {
    AssertThrow(
      std::system(
        ("cd \"" + directory + "\" && gnuplot \"" + script + "\"").c_str()) ==
        0,
      ExcMessage("gnuplot could not draw the plots of \"" + directory + "/" +
                 script +
                 "\" (gnuplot comes from the Debian package "
                 "gnuplot-nox, which scripts/setup.sh installs)."));
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



  void
  VtuWriter::initialize(const std::string &dir, const std::string &name)
  {
    directory = dir;
    basename  = name;
    records.clear();
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
  VtuWriter::write(const solver::Discretization           &discretization,
                   const Vector<double>                   &u,
                   const solver::StaticSolver::CellFields &fields,
                   const unsigned int                      step,
                   const double                            t,
                   const bool                              last)
  {
    if (when == "none" || (when == "last step" && !last))
      return;

    DataOut<3>     data_out;
    Vector<double> material_id;
    add_displacement_and_materials(data_out,
                                   discretization.dof_handler,
                                   u,
                                   material_id);
    data_out.add_data_vector(fields.J, "J");
    data_out.add_data_vector(fields.von_mises, "von_Mises_stress");
    data_out.build_patches(discretization.mapping, discretization.fe.degree);

    const std::string name =
      basename + "-" + Utilities::int_to_string(step, 4) + ".vtu";
    std::ofstream vtu(directory + "/" + name);
    data_out.write_vtu(vtu);
    AssertThrow(vtu,
                ExcMessage("Could not write \"" + directory + "/" + name +
                           "\"."));
    records.emplace_back(t, name);
    std::ofstream pvd(directory + "/" + basename + ".pvd");
    DataOutBase::write_pvd_record(pvd, records);
  }
} // namespace ddfem::report
