#include <deal.II/base/quadrature_lib.h>
#include <deal.II/base/utilities.h>
#include <deal.II/lac/vector.h>

#include <ddfem/base/exceptions.h>
#include <ddfem/base/parsing.h>
#include <ddfem/scene/boundary_conditions.h>

#include <algorithm>
#include <array>
#include <cctype>
#include <cmath>
#include <cstring>
#include <iostream>
#include <sstream>

namespace ddfem::scene
{
  namespace
  {
    /**
     * Throws ExcMessage naming @p where (whose value is @p text) if the
     * expression @p expression holds muparser syntax that is valid but
     * almost surely a typo, which would silently change the number: a ','
     * outside parentheses (a decimal comma: muparser evaluates both sides
     * and keeps the right one) or an assignment '=', '+=', ... (meant as
     * the comparison '==').
     */
    void
    check_for_typos(const std::string &expression,
                    const std::string &text,
                    const std::string &where)
    {
      const std::string start = where + " = \"" + text + "\": ";
      // Per open parenthesis: whether it holds the arguments of min(),
      // max(), sum() or avg(), which take any number of them.
      std::vector<bool> variadic;
      for (std::size_t i = 0; i < expression.size(); ++i)
        {
          const char c = expression[i];
          if (c == '(')
            {
              std::size_t name_end = i;
              while (name_end > 0 && expression[name_end - 1] == ' ')
                --name_end;
              std::size_t name_start = name_end;
              while (name_start > 0 && (std::isalnum(static_cast<unsigned char>(
                                          expression[name_start - 1])) ||
                                        expression[name_start - 1] == '_'))
                --name_start;
              const std::string name =
                expression.substr(name_start, name_end - name_start);
              variadic.push_back(name == "min" || name == "max" ||
                                 name == "sum" || name == "avg");
            }
          else if (c == ')' && !variadic.empty())
            variadic.pop_back();
          AssertThrow(c != ',' || !variadic.empty(),
                      ExcMessage(start + "a ',' outside parentheses in \"" +
                                 expression +
                                 "\" (write decimals with '.'; components "
                                 "are separated by ';')."));
          // In the arguments of min(), max(), sum() and avg(), "1,5" is a
          // decimal comma too: min(2, 1,5) would silently be min(2, 1, 5).
          // Elsewhere muparser refuses the extra argument itself.
          const auto digit = [&](const std::size_t at) {
            return std::isdigit(static_cast<unsigned char>(expression[at]));
          };
          AssertThrow(c != ',' || !variadic.back() || i == 0 ||
                        i + 1 == expression.size() || !digit(i - 1) ||
                        !digit(i + 1),
                      ExcMessage(start + "a ',' between two digits in \"" +
                                 expression +
                                 "\" (write decimals with '.'; separate the "
                                 "arguments of a function by \", \", as in "
                                 "min(1, 5))."));
          if (c == '=')
            {
              const bool comparison =
                (i + 1 < expression.size() && expression[i + 1] == '=') ||
                (i > 0 && std::string("!<>").find(expression[i - 1]) !=
                            std::string::npos);
              AssertThrow(comparison,
                          ExcMessage(start + "an assignment in \"" +
                                     expression +
                                     "\" (compare with '==', '!=', '<=' or "
                                     "'>=')."));
              i += expression[i + 1] == '=';
            }
        }
    }



    /**
     * Builds a FunctionParser from ';'-separated expressions in x, y, z. A
     * component "free" is marked unconstrained in @p constrained (if given)
     * and evaluates to 0.
     */
    std::unique_ptr<FunctionParser<3>>
    make_parser(const std::string &text,
                const unsigned int n_components,
                const std::string &where,
                std::vector<bool> *constrained = nullptr)
    {
      std::vector<std::string> expressions = split_list(text, ';', where);
      AssertThrow(expressions.size() == n_components,
                  ExcMessage(where + " = \"" + text + "\": expected " +
                             std::to_string(n_components) +
                             " expression(s) separated by ';', found " +
                             std::to_string(expressions.size()) + "."));
      if (constrained)
        constrained->assign(n_components, true);
      for (unsigned int c = 0; c < n_components; ++c)
        if (expressions[c] == "free")
          {
            AssertThrow(constrained != nullptr,
                        ExcMessage(
                          where +
                          ": 'free' is only allowed for displacements."));
            (*constrained)[c] = false;
            expressions[c]    = "0";
          }
        else
          check_for_typos(expressions[c], text, where);
      auto parser = std::make_unique<FunctionParser<3>>(n_components);
      // deal.II prints muparser's error details to std::cerr before it
      // throws; the message below says the same, once and with the
      // parameter's name.
      std::ostringstream details;
      std::streambuf    *cerr_buffer = std::cerr.rdbuf(details.rdbuf());
      const struct Restore
      {
        std::streambuf *buffer;
        ~Restore()
        {
          std::cerr.rdbuf(buffer);
        }
      } restore{cerr_buffer};
      // Each component on its own first, so that the message names the
      // one at fault: the "Column" of deal.II's message is muparser's error
      // code, and the position muparser gives counts in the component.
      for (unsigned int c = 0; c < n_components; ++c)
        try
          {
            FunctionParser<3> component(1);
            component.initialize("x,y,z",
                                 {expressions[c]},
                                 {{"pi", numbers::PI}});
            component.value(Point<3>()); // muparser parses lazily
          }
        catch (ExceptionBase &e)
          {
            std::string said   = message_of(e);
            const auto  marker = said.find("The parser said: ");
            if (marker != std::string::npos)
              said.erase(0, marker + std::strlen("The parser said: "));
            AssertThrow(false,
                        ExcMessage(
                          where + " = \"" + text + "\": " +
                          (n_components > 1 ?
                             "component " + std::to_string(c + 1) + ", \"" +
                               expressions[c] + "\", " :
                             std::string()) +
                          "is not a valid expression of x, y, z: " + said));
          }
      parser->initialize("x,y,z", expressions, {{"pi", numbers::PI}});
      return parser;
    }

    /// The body force's subsection, for messages.
    const std::string loads = "Loads";

    /**
     * Component @p component of @p parser at @p p; throws ExcMessage naming
     * the parameter (@p subsection / @p entry) and the point if the value is
     * not finite. The name is only built for the message: this runs at
     * every quadrature point.
     */
    double
    finite_value(const FunctionParser<3> &parser,
                 const Point<3>          &p,
                 const unsigned int       component,
                 const std::string       &subsection,
                 const char              *entry)
    {
      const double value = parser.value(p, component);
      if (!std::isfinite(value))
        {
          std::ostringstream message;
          message << subsection << '/' << entry << " evaluates to "
                  << (std::isnan(value) ? "nan" :
                      value > 0         ? "inf" :
                                          "-inf")
                  << " at " << format_point(p, 6)
                  << " m. Give expressions that are finite wherever they "
                     "act.";
          AssertThrow(false, ExcMessage(message.str()));
        }
      return value;
    }
  } // namespace



  Region::Region(const std::string &text,
                 const Point<3>    &extent,
                 const double       h,
                 const std::string &where)
    : name(text)
    , is_face(true)
    , upper(extent)
    , tolerance(1e-6 * h)
    , extent(extent)
  {
    const auto words = split_words(text);
    if (words.size() == 1 && words[0].size() == 2 &&
        std::string("xyz").find(words[0][0]) != std::string::npos &&
        (words[0][1] == '-' || words[0][1] == '+'))
      {
        const unsigned int d = words[0][0] - 'x';
        if (words[0][1] == '-')
          upper[d] = 0;
        else
          lower[d] = extent[d];
      }
    else
      {
        AssertThrow(words.size() == 7 && words[0] == "box",
                    ExcMessage(
                      where + " = \"" + text +
                      "\": expected a face (x-, x+, y-, y+, z-, z+) or "
                      "'box x0 y0 z0 x1 y1 z1' (meters)."));
        is_face = false;
        lower   = parse_point({words[1], words[2], words[3]}, where);
        upper   = parse_point({words[4], words[5], words[6]}, where);
        for (unsigned int d = 0; d < 3; ++d)
          AssertThrow(lower[d] <= upper[d],
                      ExcMessage(
                        where + " = \"" + text +
                        "\": the lower corner must not exceed the upper one."));
      }
  }



  bool
  Region::contains(const Point<3> &p) const
  {
    for (unsigned int d = 0; d < 3; ++d)
      if (p[d] < lower[d] - tolerance || p[d] > upper[d] + tolerance)
        return false;
    return true;
  }



  Tensor<1, 3>
  Region::face_normal() const
  {
    Tensor<1, 3> normal;
    if (is_face)
      for (unsigned int d = 0; d < 3; ++d)
        if (lower[d] == upper[d])
          normal[d] = (lower[d] == 0 ? -1 : 1);
    return normal;
  }



  Point<3>
  Region::center() const
  {
    Point<3> center;
    for (unsigned int d = 0; d < 3; ++d)
      center[d] = 0.5 * (std::clamp(lower[d], 0., extent[d]) +
                         std::clamp(upper[d], 0., extent[d]));
    return center;
  }



  void
  BoundaryConditions::declare_parameters(ParameterHandler &prm)
  {
    prm.enter_subsection("Boundary conditions");
    for (unsigned int c = 1; c <= max_conditions; ++c)
      {
        prm.enter_subsection("Condition " + std::to_string(c));
        prm.declare_entry(
          "Type",
          "none",
          Patterns::Selection(
            "none|fixed|sliding|displacement|rotation|traction|pressure"),
          "fixed: zero displacement. sliding: zero normal displacement "
          "on a face region (e.g. a floor). displacement: prescribed "
          "displacement 'Value'. rotation: rigid rotation by 'Angle' "
          "about 'Axis' through 'Center'. traction: force per reference "
          "area 'Value'. pressure: pressure 'Value' on the reference "
          "normal (positive pushes into the body). All are dead loads "
          "scaled by the load factor. Where Dirichlet conditions overlap, "
          "a displacement component takes the value of the highest-numbered "
          "condition that prescribes it.");
        prm.declare_entry(
          "Region",
          "y-",
          Patterns::Anything(),
          "Where the condition applies: a face of the grid's bounding box "
          "(x-, x+, y-, y+, z-, z+) or 'box x0 y0 z0 x1 y1 z1' (meters). "
          "Dirichlet conditions act on the nodes in the region, loads on "
          "the boundary faces whose center lies in it.");
        prm.declare_entry(
          "Value",
          "0; 0; 0",
          Patterns::Anything(),
          "displacement (m) or traction (Pa): three muparser expressions "
          "of x, y, z (reference coordinates, m) separated by ';'; a "
          "displacement component may be 'free'. pressure (Pa): one "
          "expression.");
        prm.declare_entry(
          "Axis",
          "0, 1, 0",
          Patterns::List(Patterns::Double(), 3, 3),
          "rotation: the rotation axis (normalized internally).");
        prm.declare_entry(
          "Angle",
          "90",
          Patterns::Double(-3600, 3600),
          "rotation: angle in degrees at load factor 1 (right-handed "
          "about 'Axis'), from -3600 to 3600 (ten turns); at most 90 "
          "degrees per load step.");
        prm.declare_entry(
          "Center",
          "auto",
          Patterns::Anything(),
          "rotation: a point on the axis 'x, y, z' (m), or 'auto' for the "
          "center of the region's part inside the grid (of a face region: "
          "the center of the grid's face, so give the point where the part "
          "does not fill the face).");
        prm.leave_subsection();
      }
    prm.leave_subsection();

    prm.enter_subsection("Loads");
    prm.declare_entry(
      "Body force",
      "0; 0; 0",
      Patterns::Anything(),
      "Body force per reference volume (N/m^3) at load factor 1: three "
      "muparser expressions of x, y, z separated by ';'. Gravity on a "
      "material of density 1000 kg/m^3 is '0; 0; -9.81*1000'.");
    prm.leave_subsection();
  }



  void
  BoundaryConditions::parse_parameters(ParameterHandler &prm,
                                       const Point<3>   &extent,
                                       const double      h)
  {
    conditions.clear();
    prm.enter_subsection("Boundary conditions");
    for (unsigned int c = 1; c <= max_conditions; ++c)
      {
        const std::string where =
          "Boundary conditions/Condition " + std::to_string(c);
        prm.enter_subsection("Condition " + std::to_string(c));
        Condition condition;
        condition.where = where;
        condition.type  = prm.get("Type");
        if (condition.type != "none")
          {
            condition.region = std::make_unique<Region>(prm.get("Region"),
                                                        extent,
                                                        h,
                                                        where + "/Region");
            if (condition.type == "fixed")
              condition.constrained.assign(3, true);
            else if (condition.type == "sliding")
              {
                AssertThrow(condition.region->is_face,
                            ExcMessage(where +
                                       ": 'sliding' needs a face region "
                                       "(x-, x+, y-, y+, z-, z+), not a box."));
                condition.constrained.assign(3, false);
                for (unsigned int d = 0; d < 3; ++d)
                  condition.constrained[d] =
                    (condition.region->face_normal()[d] != 0);
              }
            else if (condition.type == "displacement")
              {
                condition.value = make_parser(prm.get("Value"),
                                              3,
                                              where + "/Value",
                                              &condition.constrained);
                AssertThrow(std::count(condition.constrained.begin(),
                                       condition.constrained.end(),
                                       true) > 0,
                            ExcMessage(where + "/Value = \"" +
                                       prm.get("Value") +
                                       "\" leaves every component free, so "
                                       "the condition would do nothing: "
                                       "prescribe at least one component, or "
                                       "set its Type to none."));
              }
            else if (condition.type == "traction")
              condition.value =
                make_parser(prm.get("Value"), 3, where + "/Value");
            else if (condition.type == "pressure")
              condition.value =
                make_parser(prm.get("Value"), 1, where + "/Value");
            else if (condition.type == "rotation")
              {
                condition.axis =
                  parse_point(split_list(prm.get("Axis"), ',', where + "/Axis"),
                              where + "/Axis");
                // Scaled by its largest component first, so that its length
                // neither overflows (1e200) nor underflows (1e-200). Divided
                // component by component: Tensor's /= multiplies by the
                // inverse, which overflows for a subnormal component (1e-310).
                double largest = 0;
                for (unsigned int d = 0; d < 3; ++d)
                  largest = std::max(largest, std::abs(condition.axis[d]));
                AssertThrow(largest > 0,
                            ExcMessage(where +
                                       "/Axis must not be the zero vector."));
                for (unsigned int d = 0; d < 3; ++d)
                  condition.axis[d] = condition.axis[d] / largest;
                condition.axis /= condition.axis.norm();
                condition.angle = prm.get_double("Angle") * numbers::PI / 180.;
                condition.constrained.assign(3, true);
                const std::string center = prm.get("Center");
                if (center == "auto")
                  condition.center = condition.region->center();
                else
                  {
                    condition.center =
                      parse_point(split_list(center, ',', where + "/Center"),
                                  where + "/Center (or 'auto')");
                  }
              }
            conditions.push_back(std::move(condition));
          }
        prm.leave_subsection();
      }
    prm.leave_subsection();

    prm.enter_subsection("Loads");
    const std::string body_text = prm.get("Body force");
    body                        = make_parser(body_text, 3, "Loads/Body force");
    prm.leave_subsection();
    body_force_given = false;
    for (const std::string &e : split_list(body_text, ';', "Loads/Body force"))
      if (e != "0")
        body_force_given = true;
  }



  bool
  BoundaryConditions::Condition::prescribes(const Point<3>    &p,
                                            const unsigned int component) const
  {
    return !constrained.empty() && constrained[component] &&
           region->contains(p);
  }



  const BoundaryConditions::Condition *
  BoundaryConditions::holding_condition(const Point<3>    &p,
                                        const unsigned int component) const
  {
    const auto holder =
      std::find_if(conditions.rbegin(),
                   conditions.rend(),
                   [&](const Condition &condition) {
                     return condition.prescribes(p, component);
                   });
    return holder == conditions.rend() ? nullptr : &*holder;
  }



  bool
  BoundaryConditions::prescribes(const Point<3>    &p,
                                 const unsigned int component) const
  {
    return holding_condition(p, component) != nullptr;
  }



  bool
  BoundaryConditions::prescribed_displacement(const Point<3>    &p,
                                              const unsigned int component,
                                              const double       t,
                                              double            &value) const
  {
    const Condition *condition = holding_condition(p, component);
    if (condition == nullptr)
      return false;
    if (condition->type == "displacement")
      value = t * finite_value(
                    *condition->value, p, component, condition->where, "Value");
    else if (condition->type == "rotation")
      {
        // Rodrigues: R r = r cos(a) + (k x r) sin(a) + k (k.r)(1 - cos(a))
        const double       a       = t * condition->angle;
        const Tensor<1, 3> r       = p - condition->center;
        const Tensor<1, 3> k       = condition->axis;
        const Tensor<1, 3> rotated = r * std::cos(a) +
                                     cross_product_3d(k, r) * std::sin(a) +
                                     k * (k * r) * (1 - std::cos(a));
        value = rotated[component] - r[component];
        AssertThrow(std::isfinite(value),
                    ExcMessage(condition->where + "/Center " +
                               format_point(condition->center) +
                               " lies so far from the part that the "
                               "rotation's displacement at " +
                               format_point(p) + " is not a number."));
      }
    else
      value = 0;
    return true;
  }



  Tensor<1, 3>
  BoundaryConditions::traction(const Point<3>     &face_center,
                               const Point<3>     &p,
                               const Tensor<1, 3> &normal) const
  {
    Tensor<1, 3> t;
    for (const Condition &condition : conditions)
      if ((condition.type == "traction" || condition.type == "pressure") &&
          condition.region->contains(face_center))
        t += load(condition, p, normal);
    return t;
  }



  Tensor<1, 3>
  BoundaryConditions::load(const Condition    &condition,
                           const Point<3>     &p,
                           const Tensor<1, 3> &normal)
  {
    if (condition.type == "pressure")
      return -finite_value(*condition.value, p, 0, condition.where, "Value") *
             normal;
    Tensor<1, 3> t;
    for (unsigned int d = 0; d < 3; ++d)
      t[d] = finite_value(*condition.value, p, d, condition.where, "Value");
    return t;
  }



  std::vector<Point<3>>
  BoundaryFace::node_points(const unsigned int degree) const
  {
    Assert(degree == 1 || degree == 2, ExcIndexRange(degree, 1, 3));
    std::vector<double> unit;
    for (unsigned int i = 0; i <= degree; ++i)
      unit.push_back(double(i) / degree);
    return points(unit);
  }



  std::vector<Point<3>>
  BoundaryFace::gauss_points(const unsigned int n) const
  {
    std::vector<double> unit;
    const QGauss<1>     quadrature(n);
    for (const Point<1> &q : quadrature.get_points())
      unit.push_back(q[0]);
    return points(unit);
  }



  std::vector<Point<3>>
  BoundaryFace::points(const std::vector<double> &unit) const
  {
    unsigned int axis = 0;
    for (unsigned int d = 1; d < 3; ++d)
      if (std::abs(normal[d]) > std::abs(normal[axis]))
        axis = d;
    const unsigned int    a = (axis + 1) % 3, b = (axis + 2) % 3;
    std::vector<Point<3>> result;
    for (const double u_a : unit)
      for (const double u_b : unit)
        {
          Point<3> p = center;
          p[a] += (u_a - 0.5) * size;
          p[b] += (u_b - 0.5) * size;
          result.push_back(p);
        }
    return result;
  }



  void
  BoundaryConditions::check_regions(
    const std::vector<Point<3>>     &nodes,
    const std::vector<BoundaryFace> &boundary_faces,
    const std::vector<Point<3>>     &vertices) const
  {
    for (const Condition &condition : conditions)
      {
        const auto holds_one_of = [&](const std::vector<Point<3>> &points) {
          return std::any_of(points.begin(),
                             points.end(),
                             [&](const Point<3> &p) {
                               return condition.region->contains(p);
                             });
        };
        const bool is_load = condition.constrained.empty();
        const bool reached =
          is_load ?
            std::any_of(boundary_faces.begin(),
                        boundary_faces.end(),
                        [&](const BoundaryFace &face) {
                          return condition.region->contains(face.center);
                        }) :
            holds_one_of(nodes);
        AssertThrow(reached || is_load || !holds_one_of(vertices),
                    ExcMessage(condition.describe() +
                               " holds vertices of the solid but no "
                               "quadrature point of a face. With "
                               "DG/Dirichlet = weak, conditions act at the "
                               "quadrature points of faces: use regions that "
                               "cover faces, or DG/Dirichlet = strong."));
        AssertThrow(reached,
                    ExcMessage(condition.describe() + " acts on no " +
                               (is_load ? "boundary face" : "node") +
                               " of the solid: its region misses the solid."));
      }
  }



  void
  BoundaryConditions::check_effects(
    const std::vector<Point<3>>     &nodes,
    const std::vector<BoundaryFace> &boundary_faces,
    const unsigned int               degree,
    const bool                       weak) const
  {
    // A load on components held wherever it would act goes into the
    // reactions whole. A load that is zero on its faces is left alone: it
    // says so itself.
    for (const Condition &condition : conditions)
      if (condition.constrained.empty())
        {
          bool       nonzero = false;
          const auto acts    = [&]() {
            for (const BoundaryFace &face : boundary_faces)
              if (condition.region->contains(face.center))
                {
                  // Whether some node of the face is free in each component.
                  std::array<bool, 3> node_free{};
                  if (!weak)
                    for (const Point<3> &x : face.node_points(degree))
                      for (unsigned int d = 0; d < 3; ++d)
                        node_free[d] = node_free[d] || !prescribes(x, d);
                  for (const Point<3> &p : face.gauss_points(degree + 1))
                    {
                      // A value that is not finite here is the assembly's
                      // error.
                      Tensor<1, 3> t;
                      try
                        {
                          t = load(condition, p, face.normal);
                        }
                      catch (const ExceptionBase &)
                        {
                          continue;
                        }
                      for (unsigned int d = 0; d < 3; ++d)
                        if (t[d] != 0)
                          {
                            nonzero = true;
                            if (weak ? !prescribes(p, d) : node_free[d])
                              return true;
                          }
                    }
                }
            return false;
          };
          AssertThrow(acts() || !nonzero,
                      ExcMessage(
                        condition.describe() +
                        " loads only components that Dirichlet conditions "
                        "prescribe at every " +
                        (weak ? "quadrature point of its faces where it is not "
                                "zero (they act weakly there)" :
                                "node of the faces where it is not zero") +
                        ": all of it would go into the reactions and move "
                        "nothing. Move its region off what they hold, or free "
                        "the components it loads."));
        }

    // So does a body force on components held at every node (a region
    // given in millimeters that covers the whole part, say). It is taken
    // at the nodes: one that is zero at all of them is left alone. Weak
    // conditions hold no node.
    if (has_body_force() && !weak)
      {
        std::array<bool, 3> loaded{}, free{};
        const auto          moves = [&]() {
          return (loaded[0] && free[0]) || (loaded[1] && free[1]) ||
                 (loaded[2] && free[2]);
        };
        for (const Point<3> &x : nodes)
          {
            if (moves())
              break;
            // A value that is not finite here is the assembly's error, if
            // it is not finite where the force is integrated too.
            Tensor<1, 3> b;
            try
              {
                b = body_force(x);
              }
            catch (const ExceptionBase &)
              {
                continue;
              }
            for (unsigned int d = 0; d < 3; ++d)
              {
                loaded[d] = loaded[d] || b[d] != 0;
                free[d]   = free[d] || !prescribes(x, d);
              }
          }
        AssertThrow(!(loaded[0] || loaded[1] || loaded[2]) || moves(),
                    ExcMessage(
                      "Loads/Body force loads only components that Dirichlet "
                      "conditions prescribe at every node of the solid: all of "
                      "it would go into the reactions and move nothing. Free "
                      "the components it loads somewhere (check the regions "
                      "of the conditions: in meters, not millimeters)."));
      }

    // A component takes the value of the highest-numbered condition that
    // prescribes it, so a Dirichlet condition must keep some component of
    // some node to itself.
    for (auto condition = conditions.begin(); condition != conditions.end();
         ++condition)
      {
        if (condition->constrained.empty())
          continue;
        const auto keeps = [&](const Point<3> &p, const unsigned int d) {
          return holding_condition(p, d) == &*condition;
        };
        AssertThrow(
          std::any_of(nodes.begin(),
                      nodes.end(),
                      [&](const Point<3> &p) {
                        return condition->region->contains(p) &&
                               (keeps(p, 0) || keeps(p, 1) || keeps(p, 2));
                      }),
          ExcMessage(condition->describe() +
                     " prescribes nothing: at every node of its region, "
                     "a higher-numbered condition prescribes every component "
                     "it holds, and a component takes the value of the "
                     "highest-numbered condition. Remove it, or give it the "
                     "higher number if it should win."));
      }
  }



  void
  BoundaryConditions::check_rotation_steps(const unsigned int load_steps,
                                           const std::string &parameter) const
  {
    for (const Condition &condition : conditions)
      if (condition.type == "rotation")
        {
          // Quarter turns, with a margin for round-off: 1620 degrees read
          // back from radians as 1619.9999999999998, 180 as
          // 180.00000000000003.
          const double quarter_turns =
            std::abs(condition.angle) / (numbers::PI / 2 * (1 + 1e-12));
          const double degrees = std::abs(condition.angle) * 180. / numbers::PI;
          std::ostringstream message;
          message << condition.where << "/Angle turns by " << degrees;
          if (load_steps == 1)
            message << " degrees in one step (" << parameter << ")";
          else
            message << " degrees in " << parameter << " = " << load_steps
                    << " equal steps, " << degrees / load_steps
                    << " degrees per step";
          message
            << ": a step may turn by at most 90 "
               "degrees, since it prescribes only where each node "
               "ends, and the first step's first iterate moves the "
               "nodes along the chords of their arcs, which squeezes the part "
               "(a twisted bar midway by det F = 0.5 at 90 degrees, "
               "0.002 at 175, where solvers found states that were "
               "no solution of the turn). Use at least "
            << static_cast<unsigned int>(std::ceil(quarter_turns))
            << " load steps.";
          AssertThrow(quarter_turns <= load_steps, ExcMessage(message.str()));
        }
  }



  void
  BoundaryConditions::check_coarse_supports(const Point<3>    &extent,
                                            const double       h,
                                            const unsigned int width) const
  {
    for (const Condition &condition : conditions)
      if (!condition.constrained.empty() && !condition.region->is_face)
        for (unsigned int d = 0; d < 3; ++d)
          {
            const Region &region = *condition.region;
            const double  lower  = std::max(region.lower[d], 0.);
            const double  upper  = std::min(region.upper[d], extent[d]);
            // The voxel-grid node planes inside the box along d.
            const long first =
              std::lround(std::ceil((lower - region.tolerance) / h));
            const long last =
              std::lround(std::floor((upper + region.tolerance) / h));
            const std::string axis(1, "xyz"[d]);
            AssertThrow(
              first > last || (first % width == 0 && last % width == 0),
              ExcMessage(
                condition.describe() + ": along " + axis +
                " the region holds the voxel grid's nodes from " +
                format_number(first * h) + " m to " + format_number(last * h) +
                " m, but the coarse model, with blocks of " +
                std::to_string(width) +
                " voxels per direction, has nodes only "
                "every " +
                format_number(width * h) + " m along " + axis +
                ", so it would be held at other places than the fine one. "
                "Move the box's " +
                axis +
                " bounds so that the first and last node planes "
                "inside it are multiples of " +
                format_number(width * h) + " m."));
          }
  }



  void
  BoundaryConditions::check_weak_supports(
    const std::vector<Point<3>> &voxel_centers,
    const double                 h,
    const double                 first) const
  {
    for (const Condition &condition : conditions)
      if (!condition.constrained.empty() && !condition.region->is_face)
        for (unsigned int d = 0; d < 3; ++d)
          for (const bool upper : {false, true})
            {
              const Region &region = *condition.region;
              const double  bound  = upper ? region.upper[d] : region.lower[d];
              // The bound's place in its layer of voxels, mirrored for a
              // lower bound: from the node plane it may be on (0) past the
              // points of the layer it reaches into.
              const double layer = std::floor(bound / h);
              const double t =
                upper ? bound / h - layer : 1 - (bound / h - layer);
              const double slack = region.tolerance / h;
              if (t < first - slack || t > 1 - slack)
                continue;
              // Only a solid voxel of the layer that the box reaches
              // across the other two directions (its faces on the box's
              // sides included) is held in part.
              const auto in_part = [&](const Point<3> &c) {
                if (std::abs(c[d] - (layer + 0.5) * h) > 0.25 * h)
                  return false;
                for (unsigned int e = 0; e < 3; ++e)
                  if (e != d &&
                      (c[e] + 0.5 * h < region.lower[e] - region.tolerance ||
                       c[e] - 0.5 * h > region.upper[e] + region.tolerance))
                    return false;
                return true;
              };
              const auto held = std::find_if(voxel_centers.begin(),
                                             voxel_centers.end(),
                                             in_part);
              if (held == voxel_centers.end())
                continue;
              const std::string axis(1, "xyz"[d]);
              AssertThrow(
                false,
                ExcMessage(
                  condition.describe() + ": its " + axis + " bound " +
                  format_number(bound) + " m reaches into the voxels from " +
                  format_number(layer * h) + " to " +
                  format_number((layer + 1) * h) + " m along " + axis +
                  " past their first quadrature points (the voxel at " +
                  format_point(*held) +
                  " m, for one). With DG/Dirichlet = weak a condition holds "
                  "the quadrature points inside its region, so it would "
                  "hold faces that cross those voxels, where the continuous "
                  "model holds only the nodes on the plane at " +
                  format_number((upper ? layer : layer + 1) * h) +
                  " m. Move the bound to a node plane (" +
                  format_number(layer * h) + " or " +
                  format_number((layer + 1) * h) +
                  " m), or use DG/Dirichlet = strong."));
            }
  }



  bool
  BoundaryConditions::has_traction() const
  {
    for (const Condition &condition : conditions)
      if (condition.type == "traction" || condition.type == "pressure")
        return true;
    return false;
  }



  Tensor<1, 3>
  BoundaryConditions::body_force(const Point<3> &p) const
  {
    Tensor<1, 3> b;
    for (unsigned int d = 0; d < 3; ++d)
      b[d] = finite_value(*body, p, d, loads, "Body force");
    return b;
  }
} // namespace ddfem::scene
