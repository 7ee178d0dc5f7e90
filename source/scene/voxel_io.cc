#include <deal.II/base/exceptions.h>

#include <ddfem/base/files.h>
#include <ddfem/base/parsing.h>
#include <ddfem/scene/voxel_io.h>

#include <algorithm>
#include <charconv>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <limits>
#include <map>
#include <sstream>
#include <string_view>
#include <utility>

namespace ddfem::scene
{
  namespace
  {
    // Calls f(token) for every white-space separated token of @p text (line
    // breaks separate tokens too), without keeping them: a voxel file may
    // hold all of its ids on one line.
    template <typename Function>
    void
    for_each_token(const std::string_view text, const Function &f)
    {
      const char *white_space = " \t\n\r\v\f";
      for (std::size_t begin = text.find_first_not_of(white_space);
           begin != std::string_view::npos;)
        {
          const std::size_t end =
            std::min(text.find_first_of(white_space, begin), text.size());
          f(text.substr(begin, end - begin));
          begin = text.find_first_not_of(white_space, end);
        }
    }



    // The white-space separated tokens of @p text.
    std::vector<std::string_view>
    split(const std::string_view text)
    {
      std::vector<std::string_view> tokens;
      for_each_token(text, [&](const std::string_view token) {
        tokens.push_back(token);
      });
      return tokens;
    }



    /// A line of a text file that has a token, as for_each_line() passes it.
    struct Line
    {
      /// Its white-space separated words (with comments, those before a
      /// '#'); empty where the reader walks them with for_each_token().
      std::vector<std::string_view> tokens;
      /// The whole line.
      const std::string &text;
      /// The file and the line's number in it, counted from 1.
      const std::string &file;
      unsigned int       number;

      /// "<file>, line <n>: ", the prefix of a message about the line
      /// (built only for a message).
      std::string
      where() const
      {
        return file + ", line " + std::to_string(number) + ": ";
      }

      /// The line in double quotes for a message: at most its first 80
      /// characters, then "..." (a file may be one long line).
      std::string
      quoted() const
      {
        constexpr std::size_t shown = 80;
        return '"' + text.substr(0, shown) +
               (text.size() > shown ? "...\"" : "\"");
      }
    };



    // @p text without the UTF-8 byte order mark that editors on Windows may
    // write at the start of a file: it is no token, and no "solid" either.
    std::string_view
    without_byte_order_mark(std::string_view text)
    {
      if (text.substr(0, 3) == "\xEF\xBB\xBF")
        text.remove_prefix(3);
      return text;
    }



    // Calls f(text, words, number) for every line of @p in: its whole
    // @p text, its @p words (the part before a '#' where @p comments) and its
    // @p number, counted from 1.
    template <typename Function>
    void
    for_each_text_line(std::istream &in, const bool comments, const Function &f)
    {
      std::string text;
      for (unsigned int number = 1; std::getline(in, text); ++number)
        {
          if (number == 1)
            text = std::string(without_byte_order_mark(text));
          // A Windows line end's carriage return would show in messages
          // that quote the line.
          if (!text.empty() && text.back() == '\r')
            text.pop_back();
          const std::string_view view(text);
          f(text, comments ? view.substr(0, view.find('#')) : view, number);
        }
    }



    // Calls f(line) for every Line of @p in (read from @p file) that has a
    // token; words after a '#' are left out where @p comments.
    template <typename Function>
    void
    for_each_line(std::istream      &in,
                  const std::string &file,
                  const bool         comments,
                  const Function    &f)
    {
      for_each_text_line(in,
                         comments,
                         [&](const std::string     &text,
                             const std::string_view words,
                             const unsigned int     number) {
                           const Line line{split(words), text, file, number};
                           if (!line.tokens.empty())
                             f(line);
                         });
    }



    // Opens @p filename, or throws an error that starts with @p file and
    // says where a relative name was looked for.
    std::ifstream
    open_for_reading(const std::string       &filename,
                     const std::string       &file,
                     const std::ios::openmode mode = std::ios::in)
    {
      // (Checked before it is opened: a named pipe would wait there, and
      // /dev/zero be read until memory runs out.)
      const std::string kind = non_regular_kind(filename);
      AssertThrow(kind.empty(),
                  ExcMessage(file + ": cannot be read: it is " + kind + "."));
      std::ifstream in(filename, mode);
      const auto    path = std::filesystem::path(filename);
      AssertThrow(in,
                  ExcMessage(file + ": cannot be opened for reading" +
                             (path.is_relative() ?
                                " (a relative name is read from the working "
                                "directory: " +
                                  std::filesystem::absolute(path).string() +
                                  ")" :
                                "") +
                             "."));
      return in;
    }



    // "nx ny nz" as in the voxel file header.
    std::string
    size_string(const std::array<unsigned int, 3> &n)
    {
      return std::to_string(n[0]) + " " + std::to_string(n[1]) + " " +
             std::to_string(n[2]);
    }



    // Parses the whole token as a number, which may start with one '+' as
    // strtod() and the parameter file's numbers allow; false on any junk.
    template <typename Number>
    bool
    parse(std::string_view token, Number &value)
    {
      if (token.size() > 1 && token[0] == '+' && token[1] != '-' &&
          token[1] != '+')
        token.remove_prefix(1);
      const char *end    = token.data() + token.size();
      const auto  result = std::from_chars(token.data(), end, value);
      return result.ec == std::errc() && result.ptr == end;
    }



    // Parses tokens[first..first+2] as a point with finite coordinates.
    bool
    parse_point(const std::vector<std::string_view> &tokens,
                const std::size_t                    first,
                Point<3>                            &point)
    {
      if (tokens.size() < first + 3)
        return false;
      for (unsigned int d = 0; d < 3; ++d)
        if (!parse(tokens[first + d], point[d]) || !std::isfinite(point[d]))
          return false;
      return true;
    }



    // Builds an indexed mesh from triangle corners (three per triangle),
    // merging corners with identical coordinates. A triangle with two
    // corners at one point (a sliver of an STL export, an OBJ polygon that
    // repeats a vertex) bounds nothing and is left out, with its corners
    // unless another triangle uses them: its edge from a corner to itself
    // would fail the closedness check, and its corners would count toward
    // 'Fit to grid'.
    TriangleMesh
    merge_corners(const std::vector<Point<3>> &corners)
    {
      TriangleMesh                                  mesh;
      std::map<std::array<double, 3>, unsigned int> index_of;
      for (std::size_t t = 0; t + 2 < corners.size(); t += 3)
        {
          std::array<std::array<double, 3>, 3> keys;
          for (unsigned int c = 0; c < 3; ++c)
            keys[c] = {
              {corners[t + c][0], corners[t + c][1], corners[t + c][2]}};
          if (keys[0] == keys[1] || keys[1] == keys[2] || keys[2] == keys[0])
            continue;
          std::array<unsigned int, 3> triangle;
          for (unsigned int c = 0; c < 3; ++c)
            {
              const auto inserted = index_of.emplace(
                keys[c], static_cast<unsigned int>(mesh.vertices.size()));
              if (inserted.second)
                mesh.vertices.push_back(corners[t + c]);
              triangle[c] = inserted.first->second;
            }
          mesh.triangles.push_back(triangle);
        }
      return mesh;
    }



    // Little-endian binary STL fields.
    std::uint32_t
    read_uint32(const char *bytes)
    {
      std::uint32_t value = 0;
      for (int b = 3; b >= 0; --b)
        value = (value << 8) | static_cast<unsigned char>(bytes[b]);
      return value;
    }

    float
    read_float(const char *bytes)
    {
      const std::uint32_t bits = read_uint32(bytes);
      float               value;
      std::memcpy(&value, &bits, sizeof(value));
      return value;
    }



    // @p file is the "Surface mesh file ..." prefix for error messages.
    TriangleMesh
    read_stl(const std::string &file, const std::string &content)
    {
      std::vector<Point<3>> corners;

      // A binary file may start with "solid" too: trust the size check first.
      const std::uint64_t n_binary =
        content.size() >= 84 ? read_uint32(content.data() + 80) : 0;
      if (content.size() >= 84 && content.size() == 84 + 50 * n_binary)
        {
          for (std::uint64_t t = 0; t < n_binary; ++t)
            for (unsigned int c = 0; c < 3; ++c)
              {
                const char *bytes = content.data() + 84 + 50 * t + 12 * (c + 1);
                Point<3>    p;
                for (unsigned int d = 0; d < 3; ++d)
                  p[d] = read_float(bytes + 4 * d);
                AssertThrow(std::isfinite(p.norm_square()),
                            ExcMessage(file + ": triangle " +
                                       std::to_string(t) +
                                       " has a non-finite vertex coordinate."));
                corners.push_back(p);
              }
          return merge_corners(corners);
        }

      // A binary STL's 80-byte header may start with any bytes, those of a
      // byte order mark too: a text file's mark is skipped only here (and
      // by for_each_text_line()).
      const auto first_word =
        split(without_byte_order_mark(content).substr(0, 80));
      AssertThrow(!first_word.empty() && first_word[0] == "solid",
                  ExcMessage(file + ": is neither a binary STL (its size " +
                             std::to_string(content.size()) +
                             " bytes does not equal 84 + 50 * the triangle "
                             "count in its header) nor an ASCII STL (it does "
                             "not start with \"solid\")."));
      // Binary files often start with "solid" as well: one whose size does
      // not match its triangle count (a truncated one, say) is told apart
      // from a damaged ASCII file by the control characters (a 0 byte, say)
      // that binary floats hold and text does not.
      const bool is_text =
        std::none_of(content.begin(), content.end(), [](const char c) {
          const auto byte = static_cast<unsigned char>(c);
          return byte == 0x7F ||
                 (byte < 0x20 && std::string_view("\t\n\r\v\f").find(c) ==
                                   std::string_view::npos);
        });
      // Why a file that starts with "solid" is not read, as ASCII (@p why)
      // or as binary.
      const auto neither = [&](const std::string &why) {
        return ExcMessage(
          file + ": starts with \"solid\" but " + why +
          ", and as a binary STL its size " + std::to_string(content.size()) +
          " bytes does not equal 84 + 50 * " + std::to_string(n_binary) +
          ", the triangle count in its header (a truncated "
          "file?).");
      };
      AssertThrow(is_text || content.size() < 84, neither("holds binary data"));

      std::istringstream in(content);
      bool               in_facet        = false;
      bool               ended           = false;
      unsigned int       n_facet_corners = 0;
      for_each_line(in, file, false, [&](const Line &line) {
        const auto check = [&](const bool ok, const std::string &problem) {
          AssertThrow(ok,
                      ExcMessage(line.where() + problem + " in " +
                                 line.quoted() + "."));
        };
        const std::string_view keyword = line.tokens[0];
        Point<3>               p;
        if (keyword == "facet")
          {
            check(!in_facet, "previous facet not closed by \"endfacet\"");
            in_facet        = true;
            n_facet_corners = 0;
          }
        else if (keyword == "vertex")
          {
            check(in_facet && n_facet_corners < 3,
                  "vertex outside a facet or beyond its third vertex");
            check(line.tokens.size() == 4 && parse_point(line.tokens, 1, p),
                  "expected \"vertex x y z\" with finite coordinates");
            corners.push_back(p);
            ++n_facet_corners;
          }
        else if (keyword == "endfacet")
          {
            check(in_facet && n_facet_corners == 3,
                  "facet without exactly 3 vertices");
            in_facet = false;
          }
        else
          {
            check(keyword == "solid" || keyword == "outer" ||
                    keyword == "endloop" || keyword == "endsolid",
                  "unexpected keyword \"" + std::string(keyword) + "\"");
            // Whether the last solid so far is closed.
            ended = keyword == "endsolid" || (ended && keyword != "solid");
          }
      });
      AssertThrow(!in_facet,
                  ExcMessage(file +
                             ": ends inside a facet (missing \"endfacet\")."));
      // A file cut between facets would pass every other check.
      AssertThrow(corners.empty() || ended,
                  ExcMessage(file +
                             ": its last solid has no \"endsolid\" line after "
                             "its facets (a truncated file?)."));
      // Binary files often start with "solid" as well: one whose size does
      // not match its triangle count (a truncated one, say) gets here, and
      // has no "endsolid" line.
      AssertThrow(!corners.empty() || ended || content.size() < 84,
                  neither("has no ASCII facet"));
      return merge_corners(corners);
    }



    TriangleMesh
    read_obj(const std::string &file, const std::string &content)
    {
      std::vector<Point<3>> vertices, corners;
      std::istringstream    in(content);
      for_each_line(in, file, true, [&](const Line &line) {
        if (line.tokens[0] == "v")
          {
            // "v x y z", with an optional weight w or a colour r g b after
            // the coordinates, numbers that do not move the vertex.
            Point<3>          p;
            const std::size_t n_words = line.tokens.size();
            bool well_formed = (n_words == 4 || n_words == 5 || n_words == 7) &&
                               parse_point(line.tokens, 1, p);
            for (std::size_t t = 4; well_formed && t < n_words; ++t)
              {
                double extra = 0;
                well_formed  = parse(line.tokens[t], extra);
              }
            AssertThrow(well_formed,
                        ExcMessage(line.where() + "malformed vertex line " +
                                   line.quoted() +
                                   "; expected \"v x y z\", optionally "
                                   "followed by a weight or by r g b."));
            vertices.push_back(p);
          }
        else if (line.tokens[0] == "f")
          {
            AssertThrow(line.tokens.size() >= 4,
                        ExcMessage(line.where() +
                                   "a face needs at least 3 "
                                   "vertices: " +
                                   line.quoted() + "."));
            // Vertex indices are 1-based, negative ones count from the
            // last vertex read; "a/b/c" forms carry the vertex index first.
            std::vector<unsigned int> face;
            for (std::size_t t = 1; t < line.tokens.size(); ++t)
              {
                const std::string_view token = line.tokens[t];
                long long              index = 0;
                AssertThrow(parse(token.substr(0, token.find('/')), index),
                            ExcMessage(line.where() +
                                       "malformed face vertex \"" +
                                       std::string(token) + "\"."));
                const long long n_vertices = vertices.size();
                const long long v = index > 0 ? index - 1 : n_vertices + index;
                AssertThrow(index != 0 && v >= 0 && v < n_vertices,
                            ExcMessage(line.where() + "vertex index " +
                                       std::to_string(index) +
                                       " is out of range (" +
                                       std::to_string(n_vertices) +
                                       " vertices defined so far)."));
                face.push_back(static_cast<unsigned int>(v));
              }
            for (std::size_t c = 1; c + 1 < face.size(); ++c)
              for (const unsigned int v : {face[0], face[c], face[c + 1]})
                corners.push_back(vertices[v]);
          }
      });
      // As an STL file's corners: vertices at the same place become one
      // (a mesh written as a triangle soup is closed), and vertices no face
      // uses do not count toward 'Fit to grid'.
      return merge_corners(corners);
    }



    // Twice the signed area of (a,b,p) in the xy plane. The edge is always
    // evaluated in one canonical direction, so the two triangles sharing it
    // get exactly opposite values and a ray cannot slip through or hit both.
    // An exact zero is resolved by the symbolic perturbation p + (eps, eps^2)
    // and returned as the smallest number of that sign.
    double
    edge_function(const Point<3> &a,
                  const Point<3> &b,
                  const double    x,
                  const double    y)
    {
      const bool flip = std::make_pair(a[0], a[1]) > std::make_pair(b[0], b[1]);
      const Point<3> &u = flip ? b : a;
      const Point<3> &v = flip ? a : b;
      double value = (v[0] - u[0]) * (y - u[1]) - (v[1] - u[1]) * (x - u[0]);
      if (value == 0)
        {
          const double tie = (v[1] != u[1]) ? u[1] - v[1] : v[0] - u[0];
          if (tie != 0)
            value =
              std::copysign(std::numeric_limits<double>::denorm_min(), tie);
        }
      return flip ? -value : value;
    }



    /**
     * Edge @p e (0, 1 or 2, from corner e to corner e+1) of triangle @p t
     * of @p mesh: its vertex indices, lower first, and +1 where the
     * triangle runs along it from the lower to the higher, -1 the other way.
     */
    std::pair<std::pair<unsigned int, unsigned int>, int>
    edge_of(const TriangleMesh &mesh,
            const unsigned int  t,
            const unsigned int  e)
    {
      const unsigned int a = mesh.triangles[t][e],
                         b = mesh.triangles[t][(e + 1) % 3];
      // A copy: std::minmax returns references to a and b.
      const std::pair<unsigned int, unsigned int> key = std::minmax(a, b);
      return {key, a < b ? 1 : -1};
    }



    /**
     * The triangles on each edge of @p mesh (see edge_of()), each with the
     * direction it runs along the edge.
     */
    std::map<std::pair<unsigned int, unsigned int>,
             std::vector<std::pair<unsigned int, int>>>
    triangles_on_edges(const TriangleMesh &mesh)
    {
      std::map<std::pair<unsigned int, unsigned int>,
               std::vector<std::pair<unsigned int, int>>>
        edges;
      for (unsigned int t = 0; t < mesh.triangles.size(); ++t)
        for (unsigned int e = 0; e < 3; ++e)
          {
            const auto [key, direction] = edge_of(mesh, t, e);
            edges[key].emplace_back(t, direction);
          }
      return edges;
    }



    /**
     * For each triangle of @p mesh, +1 to keep it as it is or -1 to reverse
     * it, so that every shell (the triangles joined by edges of exactly two
     * triangles) is oriented consistently, each the way most of its
     * triangles are: a few reversed triangles are repaired, and a cavity's
     * shell that faces inward stays so. Empty if a shell cannot be
     * oriented or has as many triangles one way as the other, or an edge of
     * more than two triangles then runs more often one way than the other.
     */
    std::vector<int>
    consistent_orientation(const TriangleMesh &mesh)
    {
      const auto edges = triangles_on_edges(mesh);

      std::vector<int> sign(mesh.triangles.size(), 0); // 0: not reached
      for (unsigned int seed = 0; seed < sign.size(); ++seed)
        if (sign[seed] == 0)
          {
            // A neighbor runs along the shared edge the other way.
            std::vector<unsigned int> shell = {seed};
            sign[seed]                      = 1;
            for (std::size_t next = 0; next < shell.size(); ++next)
              for (unsigned int e = 0; e < 3; ++e)
                {
                  const unsigned int t        = shell[next];
                  const auto [key, direction] = edge_of(mesh, t, e);
                  const auto &on_edge         = edges.at(key);
                  if (on_edge.size() != 2)
                    continue;
                  const auto &other =
                    on_edge[0].first == t ? on_edge[1] : on_edge[0];
                  const int wanted = -sign[t] * direction * other.second;
                  if (sign[other.first] == 0)
                    {
                      sign[other.first] = wanted;
                      shell.push_back(other.first);
                    }
                  else if (sign[other.first] != wanted)
                    return {};
                }
            const auto reversed =
              std::count_if(shell.begin(),
                            shell.end(),
                            [&](const unsigned int t) { return sign[t] < 0; });
            // Half of each way: no orientation to prefer.
            if (2 * static_cast<std::size_t>(reversed) == shell.size())
              return {};
            if (2 * static_cast<std::size_t>(reversed) > shell.size())
              for (const unsigned int t : shell)
                sign[t] = -sign[t];
          }

      for (const auto &[key, on_edge] : edges)
        {
          int balance = 0;
          for (const auto &[t, direction] : on_edge)
            balance += sign[t] * direction;
          if (balance != 0)
            return {};
        }
      return sign;
    }
  } // namespace



  void
  read_voxel_file(const std::string &filename,
                  const unsigned int n_ids,
                  VoxelGrid         &grid)
  {
    const std::string file = "Voxel file \"" + filename + "\"";
    std::ifstream     in   = open_for_reading(filename, file);

    const auto       &n      = grid.size();
    const std::string header = size_string(n);
    // Ids are stored as MaterialId, which caps the usable range.
    const unsigned long id_bound =
      std::min<unsigned long>(n_ids,
                              std::numeric_limits<MaterialId>::max() + 1ul);

    std::vector<MaterialId> ids;
    ids.reserve(grid.n_voxels());
    std::size_t n_found     = 0;
    bool        have_header = false;
    // The ids are walked token by token: a file may hold them all on one
    // line, and a vector of their views would take 16 bytes for each.
    for_each_text_line(
      in,
      true,
      [&](const std::string     &text,
          const std::string_view words,
          const unsigned int     number) {
        if (!have_header)
          {
            const Line line{split(words), text, file, number};
            if (line.tokens.empty())
              return;
            std::array<unsigned int, 3> m;
            AssertThrow(line.tokens.size() == 3 &&
                          parse(line.tokens[0], m[0]) &&
                          parse(line.tokens[1], m[1]) &&
                          parse(line.tokens[2], m[2]),
                        ExcMessage(line.where() +
                                   "expected the header \"nx ny nz\" on a "
                                   "line of its own, found " +
                                   line.quoted() + "."));
            AssertThrow(m == n,
                        ExcMessage(line.where() + "the header \"" +
                                   size_string(m) +
                                   "\" does not match Geometry/Grid size "
                                   "= \"" +
                                   header + "\"."));
            have_header = true;
            return;
          }

        const Line line{{}, text, file, number};
        for_each_token(words, [&](const std::string_view token) {
          unsigned long id = 0;
          AssertThrow(parse(token, id),
                      ExcMessage(line.where() + "\"" + std::string(token) +
                                 "\" is not a non-negative integer "
                                 "material id less than " +
                                 std::to_string(id_bound) + "."));
          if (ids.size() < grid.n_voxels())
            {
              AssertThrow(id < id_bound,
                          ExcMessage(line.where() + "material id " +
                                     std::to_string(id) + " of " +
                                     grid.voxel_name(ids.size()) +
                                     " is out of range: ids must be less "
                                     "than " +
                                     std::to_string(id_bound) + "."));
              ids.push_back(static_cast<MaterialId>(id));
            }
          ++n_found;
        });
      });

    AssertThrow(have_header,
                ExcMessage(file + ": no header \"nx ny nz\" found."));
    AssertThrow(n_found == grid.n_voxels(),
                ExcMessage(file + ": expected " +
                           std::to_string(grid.n_voxels()) +
                           " material ids after the header \"" + header +
                           "\", found " + std::to_string(n_found) + "."));

    for (std::size_t v = 0; v < ids.size(); ++v)
      grid[v] = ids[v];
  }



  TriangleMesh
  read_surface_mesh(const std::string &filename)
  {
    const std::string file = "Surface mesh file \"" + filename + "\"";

    const std::string extension = lowercase_extension(filename);
    AssertThrow(extension == ".stl" || extension == ".obj",
                ExcMessage(file + ": unknown extension \"" + extension +
                           "\"; expected .stl or .obj."));

    std::ifstream in = open_for_reading(filename, file, std::ios::binary);
    std::string   content((std::istreambuf_iterator<char>(in)),
                        std::istreambuf_iterator<char>());
    TriangleMesh  mesh =
      extension == ".stl" ? read_stl(file, content) : read_obj(file, content);
    AssertThrow(
      !mesh.triangles.empty(),
      ExcMessage(file + ": contains no triangle with three distinct corners."));
    // voxelize() tells inside from outside by counting crossings, which
    // needs a closed surface: every edge on an even number of triangles.
    for (const auto &[edge, on_edge] : triangles_on_edges(mesh))
      if (const std::size_t count = on_edge.size(); count % 2 != 0)
        {
          AssertThrow(false,
                      ExcMessage(
                        file + ": is not a closed surface: the edge from " +
                        format_point(mesh.vertices[edge.first]) + " to " +
                        format_point(mesh.vertices[edge.second]) +
                        " belongs to " + std::to_string(count) + " triangle" +
                        (count == 1 ? "" : "s") +
                        ". Layout/Surface mesh needs a closed "
                        "(watertight) mesh."));
        }
    return mesh;
  }



  void
  fit_to_box(TriangleMesh &mesh, const Point<3> &lower, const Point<3> &upper)
  {
    AssertThrow(!mesh.vertices.empty(),
                ExcMessage("the mesh has no vertices."));

    Point<3> min = mesh.vertices[0], max = mesh.vertices[0];
    for (const Point<3> &p : mesh.vertices)
      for (unsigned int d = 0; d < 3; ++d)
        {
          min[d] = std::min(min[d], p[d]);
          max[d] = std::max(max[d], p[d]);
        }

    double   scale = std::numeric_limits<double>::infinity();
    Point<3> mesh_center, box_center;
    for (unsigned int d = 0; d < 3; ++d)
      {
        AssertThrow(upper[d] > lower[d],
                    ExcMessage("the target box is empty along "
                               "axis " +
                               std::to_string(d) + "."));
        AssertThrow(std::isfinite(max[d] - min[d]),
                    ExcMessage("its extent along axis " + std::to_string(d) +
                               " is too large to be a number."));
        if (max[d] > min[d])
          scale = std::min(scale, (upper[d] - lower[d]) / (max[d] - min[d]));
        mesh_center[d] = 0.5 * (min[d] + max[d]);
        box_center[d]  = 0.5 * (lower[d] + upper[d]);
      }
    // All vertices at one place, or an extent so small (subnormal) that
    // the scale overflows.
    AssertThrow(std::isfinite(scale),
                ExcMessage("its extent " + format_point(Point<3>(max - min)) +
                           " is too small to be scaled to the grid."));

    for (Point<3> &p : mesh.vertices)
      p = box_center + scale * (p - mesh_center);
  }



  void
  voxelize(const TriangleMesh &mesh, const MaterialId material, VoxelGrid &grid)
  {
    const auto  &n = grid.size();
    const double h = grid.voxel_size();
    // Ray (i,j) runs parallel to z through ((i+1/2)h + dx, (j+1/2)h + dy),
    // and voxel k's center on it lies at (k+1/2)h + dz: a face exactly on a
    // row of voxel centers keeps them inside where it bounds the body from
    // below, outside where it bounds it from above, whatever the round-off
    // of the crossing's height.
    const double dx = 1e-7 * h * (std::sqrt(2.) - 1);
    const double dy = 1e-7 * h * (std::sqrt(3.) - 1);
    const double dz = 1e-7 * h * (std::sqrt(5.) - 2);

    // Half-open range of ray indices whose coordinate may lie in [low, high];
    // rounded outwards, the exact test below decides.
    const auto ray_range = [h](const double       low,
                               const double       high,
                               const double       offset,
                               const unsigned int n_rays) {
      const auto clamp = [n_rays](const double r) {
        return static_cast<unsigned int>(std::clamp(r, 0., double(n_rays)));
      };
      return std::make_pair(clamp(std::floor((low - offset) / h - 0.5)),
                            clamp(std::ceil((high - offset) / h - 0.5) + 1));
    };

    // Bin the triangles by the rows of columns (j) their xy bounding box
    // covers, and each row's by its columns (i) when the row is voxelized.
    // The bins span the rays the mesh may cross, not the grid: bins for
    // every row or column of a long grid (up to 2e8 voxels along an axis)
    // would take GBs, and the rays outside cross nothing.
    std::vector<std::pair<unsigned int, unsigned int>> i_ranges(
      mesh.triangles.size()),
      j_ranges(mesh.triangles.size());
    unsigned int i_first = n[0], i_last = 0, j_first = n[1], j_last = 0;
    for (unsigned int t = 0; t < mesh.triangles.size(); ++t)
      {
        Point<3> low = mesh.vertices[mesh.triangles[t][0]], high = low;
        for (const unsigned int v : mesh.triangles[t])
          for (unsigned int d = 0; d < 2; ++d)
            {
              low[d]  = std::min(low[d], mesh.vertices[v][d]);
              high[d] = std::max(high[d], mesh.vertices[v][d]);
            }
        i_ranges[t] = ray_range(low[0], high[0], dx, n[0]);
        j_ranges[t] = ray_range(low[1], high[1], dy, n[1]);
        if (i_ranges[t].first < i_ranges[t].second &&
            j_ranges[t].first < j_ranges[t].second)
          {
            i_first = std::min(i_first, i_ranges[t].first);
            i_last  = std::max(i_last, i_ranges[t].second);
            j_first = std::min(j_first, j_ranges[t].first);
            j_last  = std::max(j_last, j_ranges[t].second);
          }
      }
    if (i_first >= i_last) // no triangle over the grid
      return;
    std::vector<std::vector<unsigned int>> row_triangles(j_last - j_first);
    for (unsigned int t = 0; t < mesh.triangles.size(); ++t)
      if (i_ranges[t].first < i_ranges[t].second)
        for (unsigned int j = j_ranges[t].first; j < j_ranges[t].second; ++j)
          row_triangles[j - j_first].push_back(t);
    std::vector<std::vector<unsigned int>> column_triangles(i_last - i_first);

    // Overlapping bodies of a mesh that can be oriented consistently make
    // a union (inside: nonzero winding number); otherwise inside is odd
    // parity.
    const std::vector<int> orientation = consistent_orientation(mesh);
    const bool             winding     = !orientation.empty();
    std::vector<std::pair<double, int>> crossings; // z, winding change
    for (unsigned int j = j_first; j < j_last; ++j)
      {
        for (std::vector<unsigned int> &column : column_triangles)
          column.clear();
        for (const unsigned int t : row_triangles[j - j_first])
          for (unsigned int i = i_ranges[t].first; i < i_ranges[t].second; ++i)
            column_triangles[i - i_first].push_back(t);
        for (unsigned int i = i_first; i < i_last; ++i)
          {
            const double x = (i + 0.5) * h + dx;
            const double y = (j + 0.5) * h + dy;
            crossings.clear();
            for (const unsigned int t : column_triangles[i - i_first])
              {
                const Point<3> &a = mesh.vertices[mesh.triangles[t][0]];
                const Point<3> &b = mesh.vertices[mesh.triangles[t][1]];
                const Point<3> &c = mesh.vertices[mesh.triangles[t][2]];
                // Unnormalized barycentric coordinates of the ray in xy.
                const double la = edge_function(b, c, x, y);
                const double lb = edge_function(c, a, x, y);
                const double lc = edge_function(a, b, x, y);
                // A triangle seen counterclockwise from above (la + lb + lc
                // > 0) faces up: where it is outward, the ray leaves there.
                if ((la > 0 && lb > 0 && lc > 0) ||
                    (la < 0 && lb < 0 && lc < 0))
                  crossings.emplace_back((la * a[2] + lb * b[2] + lc * c[2]) /
                                           (la + lb + lc),
                                         (la > 0 ? -1 : 1) *
                                           (winding ? orientation[t] : 1));
              }
            std::sort(crossings.begin(), crossings.end());

            // Voxel centers in [z_m, z_{m+1}) are inside if the winding
            // number (or the parity) after crossing m says so.
            int inside = 0;
            for (std::size_t m = 0; m + 1 < crossings.size(); ++m)
              {
                inside = winding ? inside + crossings[m].second : 1 - inside;
                if (inside == 0)
                  continue;
                const auto k_index = [&](const double z) {
                  return static_cast<unsigned int>(std::clamp(
                    std::ceil((z - dz) / h - 0.5), 0., double(n[2])));
                };
                const unsigned int k_begin = k_index(crossings[m].first);
                const unsigned int k_end   = k_index(crossings[m + 1].first);
                for (unsigned int k = k_begin; k < k_end; ++k)
                  grid(i, j, k) = material;
              }
          }
      }
  }
} // namespace ddfem::scene
