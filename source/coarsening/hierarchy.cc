#include <deal.II/base/geometry_info.h>

#include <ddfem/base/parsing.h>
#include <ddfem/coarsening/hierarchy.h>
#include <ddfem/material/kernel.h>

#include <algorithm>
#include <iomanip>
#include <map>
#include <sstream>

#include "hdf5_io.h"

namespace ddfem::coarsening
{
  using namespace hdf5;

  void
  HierarchySettings::declare_parameters(ParameterHandler &prm)
  {
    prm.enter_subsection("Level 2");
    prm.declare_entry("Level-1 classes",
                      "400",
                      Patterns::Integer(1, 1000),
                      "The level-1 metamaterials are clustered into this many "
                      "classes, the second level's palette. At most 1000: "
                      "the next stage clusters the (n+1)^2 pairs of classes "
                      "by 32 features each, about 0.3 GB at 1000.");
    prm.declare_entry("Intermediate representatives",
                      "400",
                      Patterns::Integer(1, 1000),
                      "Representatives kept after the 2x1x1 and the 1x2x1 "
                      "stage (the paper keeps 400). At most 1000, for the "
                      "same reason as Level-1 classes.");
    prm.declare_entry("Representatives",
                      "400",
                      Patterns::Integer(1, 10000),
                      "Second-level metamaterials (after the 1x1x2 stage); "
                      "each one is sampled and fitted with 64 points. A "
                      "scene's 4x4x4 blocks are picked first at every "
                      "stage, so within these budgets each is fitted as "
                      "it is. At most 10000 (hours of fits).");
    prm.declare_entry(
      "Regularization",
      "1",
      Patterns::Double(0, max_regularization),
      "Weight of the regularization of the 64-point fits toward the "
      "children's records (Database/Fitting/Regularization is the "
      "level-1 weight). A 64-point fit has 192 parameters; with less weight it makes the "
      "element too soft in deformations the samples do not cover "
      "(doc/coarsening.md). A run that fits level 2 needs it above 0: the "
      "element moves its 64 points by its 8 corners, so no samples "
      "determine every parameter (1e-6 leaves them nearly free).");
    prm.leave_subsection();
  }



  void
  HierarchySettings::parse_parameters(ParameterHandler &prm)
  {
    prm.enter_subsection("Level 2");
    n_classes         = prm.get_integer("Level-1 classes");
    n_intermediate    = prm.get_integer("Intermediate representatives");
    n_representatives = prm.get_integer("Representatives");
    regularization    = prm.get_double("Regularization");
    prm.leave_subsection();
  }



  std::string
  HierarchySettings::fingerprint() const
  {
    std::ostringstream s;
    s << std::setprecision(17) << "level-1 classes: " << n_classes
      << ", intermediate: " << n_intermediate
      << ", representatives: " << n_representatives
      << ", regularization: " << without_negative_zero(regularization)
      << ", point offset: " << point_offset
      << ", sampler version: " << sampler_version;
    return s.str();
  }



  bool
  HierarchySettings::fits_like(const HierarchySettings &other) const
  {
    return regularization == other.regularization &&
           point_offset == other.point_offset &&
           sampler_version == other.sampler_version;
  }



  namespace
  {
    /// Level-1 classes at the positions of a stage-@p s class: positions
    /// are numbered by their coordinates' bits (x first).
    std::vector<std::int32_t>
    expand(const std::array<std::vector<std::int32_t>, 3> &pairs,
           const std::array<unsigned int, 4>              &n_classes,
           const int                                       s,
           const std::int32_t                              c)
    {
      if (s < 0)
        return {c};
      if (c == std::int32_t(n_classes[s + 1])) // void
        return std::vector<std::int32_t>(2u << s, n_classes[0]);
      std::vector<std::int32_t> low =
        expand(pairs, n_classes, s - 1, pairs[s][2 * c]);
      const std::vector<std::int32_t> high =
        expand(pairs, n_classes, s - 1, pairs[s][2 * c + 1]);
      low.insert(low.end(), high.begin(), high.end());
      return low;
    }

    /// Whether a stage's pair of classes (@p a, @p b) of the previous
    /// stage, @p n_previous of them (class n_previous: void), exists: not
    /// both halves void, and a void half only in a palette with void.
    bool
    pair_exists(const std::uint64_t a,
                const std::uint64_t b,
                const std::uint64_t n_previous,
                const bool          with_void)
    {
      return !(a == n_previous && b == n_previous) &&
             (with_void || (a < n_previous && b < n_previous));
    }
  } // namespace



  BlockKeys
  Hierarchy::keys(const Database                   &level1,
                  const std::array<Combination, 8> &blocks)
  {
    check_representable(level1.combinations(), blocks);
    BlockKeys result;
    for (unsigned int p = 0; p < 8; ++p)
      result[p] = all_void(blocks[p]) ?
                    -1 :
                    std::int64_t(level1.combinations().key(blocks[p]));
    return result;
  }



  void
  Hierarchy::build_tables(const Database               &level1,
                          const HierarchySettings      &new_settings,
                          const std::vector<BlockKeys> &required_blocks)
  {
    settings = new_settings;
    required = required_blocks;
    std::sort(required.begin(), required.end());
    required.erase(std::unique(required.begin(), required.end()),
                   required.end());
    const CoarseElement element(1, child_point_offset);

    // The second level's palette: clusters of the level-1 metamaterials,
    // the required blocks' sub-blocks first.
    std::vector<std::size_t> keys;
    const auto               level1_features =
      level1.features(element, compression_deformations(), keys, Fit::child);
    std::vector<unsigned int> required_classes;
    for (const BlockKeys &block : required)
      for (const std::int64_t key : block)
        if (key >= 0)
          {
            const auto at = std::lower_bound(keys.begin(), keys.end(), key);
            AssertThrow(at != keys.end() && std::int64_t(*at) == key,
                        ExcInternalError());
            required_classes.push_back(at - keys.begin());
          }
    const Clustering classes =
      cluster(level1_features, settings.n_classes, 20260102, required_classes);
    const unsigned int n1 = classes.representatives.size();
    class_of.assign(level1.combinations().size(), n1);
    for (unsigned int p = 0; p < keys.size(); ++p)
      class_of[keys[p]] = classes.nearest[p];
    class_key.clear();
    for (const unsigned int r : classes.representatives)
      class_key.push_back(keys[r]);
    std::vector<Metamaterial> class_material;
    for (const auto key : class_key)
      class_material.push_back(
        level1.lookup(level1.combinations().combination(key), Fit::child));

    // The required blocks' classes at the current stage (void = n1).
    std::vector<std::array<std::int32_t, 8>> required_at;
    for (const BlockKeys &block : required)
      {
        std::array<std::int32_t, 8> c;
        for (unsigned int p = 0; p < 8; ++p)
          c[p] = block[p] < 0 ? n1 : class_of[block[p]];
        required_at.push_back(c);
      }

    std::array<unsigned int, 4> n_classes = {{n1, 0, 0, 0}};
    for (unsigned int s = 0; s < 3; ++s)
      {
        // Common deformations of the composite block of stage s (two,
        // four, eight level-1 elements) and each level-1 class's energy
        // at each position in it.
        const unsigned int n_positions = 2u << s;
        const Point<3>     size(2, s >= 1 ? 2 : 1, s >= 2 ? 2 : 1);
        const std::vector<CornerDisplacements> deformations =
          compression_deformations(s);
        const unsigned int n_deformations = deformations.size();
        // energy[d][position][class]
        std::vector<std::vector<std::vector<double>>> energy(
          n_deformations,
          std::vector<std::vector<double>>(n_positions,
                                           std::vector<double>(n1 + 1, 0.)));
        std::vector<Tensor<2, 3>> F;
        for (unsigned int d = 0; d < n_deformations; ++d)
          {
            const CornerDisplacements       &composite = deformations[d];
            std::vector<CornerDisplacements> child(n_positions);
            double                           largest = 0;
            for (unsigned int p = 0; p < n_positions; ++p)
              {
                for (unsigned int v = 0; v < 8; ++v)
                  {
                    Point<3> x;
                    for (unsigned int i = 0; i < 3; ++i)
                      x[i] = (((p >> i) & 1) + ((v >> i) & 1)) / size[i];
                    for (unsigned int w = 0; w < 8; ++w)
                      child[p][v] +=
                        GeometryInfo<3>::d_linear_shape_function(x, w) *
                        composite[w];
                  }
                element.deformation_gradients(child[p], F);
                for (const auto &Fq : F)
                  largest = std::max(largest, material::linearized_strain(Fq));
              }
            for (unsigned int p = 0; p < n_positions; ++p)
              {
                for (auto &corner : child[p])
                  corner *= 0.1 / largest;
                for (unsigned int c = 0; c < n1; ++c)
                  AssertThrow(element.energy(child[p],
                                             class_material[c],
                                             energy[d][p][c]),
                              ExcInternalError());
              }
          }

        // Features of every pair of the previous stage's classes.
        const unsigned int               n_previous = n_classes[s];
        std::vector<std::vector<double>> features;
        std::vector<std::int32_t>        candidates;
        for (unsigned int b = 0; b <= n_previous; ++b)
          for (unsigned int a = 0; a <= n_previous; ++a)
            {
              if (!pair_exists(
                    a, b, n_previous, level1.combinations().with_void()))
                continue;
              std::vector<std::int32_t> at =
                expand(pairs, n_classes, int(s) - 1, a);
              const std::vector<std::int32_t> high =
                expand(pairs, n_classes, int(s) - 1, b);
              at.insert(at.end(), high.begin(), high.end());
              std::vector<double> feature(n_deformations);
              for (unsigned int d = 0; d < n_deformations; ++d)
                {
                  double sum = 0;
                  for (unsigned int p = 0; p < n_positions; ++p)
                    sum += energy[d][p][at[p]];
                  feature[d] = std::log(sum);
                }
              features.push_back(feature);
              candidates.push_back(a + (n_previous + 1) * b);
            }
        // The required blocks' pairs at this stage.
        const unsigned int        width = 8u >> (s + 1);
        std::vector<unsigned int> required_pairs;
        for (const auto &c : required_at)
          for (unsigned int p = 0; p < width; ++p)
            {
              // Candidates are sorted; an all-void pair is none.
              const std::int32_t pair =
                c[2 * p] + std::int32_t(n_previous + 1) * c[2 * p + 1];
              const auto at =
                std::lower_bound(candidates.begin(), candidates.end(), pair);
              if (at != candidates.end() && *at == pair)
                required_pairs.push_back(at - candidates.begin());
            }
        const unsigned int n_wanted =
          s < 2 ? settings.n_intermediate : settings.n_representatives;
        const Clustering stage =
          cluster(features, n_wanted, 20260103 + s, required_pairs);
        n_classes[s + 1] = stage.representatives.size();
        table[s].assign((n_previous + 1) * (n_previous + 1), n_classes[s + 1]);
        for (unsigned int p = 0; p < candidates.size(); ++p)
          table[s][candidates[p]] = stage.nearest[p];
        pairs[s].clear();
        for (const unsigned int r : stage.representatives)
          {
            pairs[s].push_back(candidates[r] % (n_previous + 1));
            pairs[s].push_back(candidates[r] / (n_previous + 1));
          }
        for (auto &c : required_at)
          pair_up(s, c);
      }
    entries.clear();
  }



  std::array<Combination, 8>
  Hierarchy::composition(const Database &level1, const unsigned int r) const
  {
    const std::array<unsigned int, 4> n_classes = {
      {static_cast<unsigned int>(class_key.size()),
       static_cast<unsigned int>(pairs[0].size() / 2),
       static_cast<unsigned int>(pairs[1].size() / 2),
       static_cast<unsigned int>(pairs[2].size() / 2)}};
    const std::vector<std::int32_t> at = expand(pairs, n_classes, 2, r);
    std::array<Combination, 8>      blocks;
    for (unsigned int p = 0; p < 8; ++p)
      blocks[p] = (at[p] == std::int32_t(class_key.size())) ?
                    Combination{} :
                    level1.combinations().combination(class_key[at[p]]);
    return blocks;
  }



  bool
  Hierarchy::covers(const Database                 &level1,
                    const std::vector<Combination> &combinations,
                    const std::vector<BlockKeys>   &blocks) const
  {
    const bool knows_combinations =
      std::all_of(combinations.begin(),
                  combinations.end(),
                  [&](const Combination &c) {
                    if (all_void(c))
                      return true;
                    level1.combinations().check_covered(c);
                    return std::size_t(class_of[level1.combinations().key(c)]) <
                           class_key.size();
                  });
    // Tables built for no block in particular (Scope = all) represent
    // every block by its nearest representative.
    return knows_combinations &&
           (required.empty() ||
            std::all_of(blocks.begin(), blocks.end(), [&](const BlockKeys &b) {
              return std::all_of(b.begin(),
                                 b.end(),
                                 [](auto key) { return key < 0; }) ||
                     std::binary_search(required.begin(), required.end(), b);
            }));
  }



  void
  Hierarchy::keep_entries(const Database &level1, const Hierarchy &old)
  {
    std::map<BlockKeys, unsigned int> representative;
    for (unsigned int r = 0; r < n_representatives(); ++r)
      representative[keys(level1, composition(level1, r))] = r;
    entries.clear();
    for (const Entry &e : old.entries)
      {
        const auto match =
          representative.find(keys(level1, old.composition(level1, e.key)));
        if (match != representative.end())
          {
            entries.push_back(e);
            entries.back().key = match->second;
          }
      }
    sort_by_key(entries);
  }



  void
  Hierarchy::pair_up(const unsigned int s, std::array<std::int32_t, 8> &c) const
  {
    const std::size_t n =
      (s == 0 ? class_key.size() : pairs[s - 1].size() / 2) + 1;
    for (unsigned int p = 0; p < (8u >> (s + 1)); ++p)
      c[p] = table[s][c[2 * p] + n * c[2 * p + 1]];
  }



  void
  Hierarchy::check_representable(const CombinationIndex           &level1,
                                 const std::array<Combination, 8> &blocks)
  {
    for (const Combination &c : blocks)
      level1.check_covered(c);
    const auto n_void = std::count_if(blocks.begin(), blocks.end(), all_void);
    AssertThrow(level1.with_void() || n_void == 0 || n_void == 8,
                ExcMessage("A 4x4x4 block holds void 2x2x2 blocks next to "
                           "solid ones, and the metamaterial database was "
                           "built with Database/Include void = false, so it "
                           "has no level-2 metamaterial for that block. Use "
                           "a database with void, or coarsening level 1."));
  }



  int
  Hierarchy::find(const Database                   &level1,
                  const std::array<Combination, 8> &blocks) const
  {
    const BlockKeys             block = keys(level1, blocks);
    std::array<std::int32_t, 8> c;
    for (unsigned int p = 0; p < 8; ++p)
      {
        c[p] = block[p] < 0 ? class_key.size() : class_of[block[p]];
        AssertThrow(block[p] < 0 || c[p] < std::int32_t(class_key.size()),
                    ExcMessage("The level-2 tables of the metamaterial "
                               "database predate a level-1 entry this "
                               "block needs; run the scene's database build "
                               "again (Run type = database) to renew them."));
      }
    // Pair along x, then y, then z.
    for (unsigned int s = 0; s < 3; ++s)
      pair_up(s, c);
    return c[0] == std::int32_t(n_representatives()) ? -1 : c[0];
  }



  Metamaterial
  Hierarchy::lookup(const Database                   &level1,
                    const std::array<Combination, 8> &blocks) const
  {
    const int r = find(level1, blocks);
    AssertThrow(r >= 0, ExcMessage("A void 4x4x4 block has no metamaterial."));
    const auto entry = find_key(entries, r);
    AssertThrow(entry != entries.end() && entry->key == std::size_t(r),
                ExcMessage("The second-level metamaterial " +
                           std::to_string(r) + " has not been fitted."));
    return entry->material;
  }
} // namespace ddfem::coarsening



namespace ddfem::coarsening
{
  void
  Hierarchy::save(const std::int64_t file) const
  {
    write_attribute(file, "level 2 settings", settings.fingerprint());
    write_dataset(file,
                  "level2/class of",
                  {hsize_t(class_of.size())},
                  class_of);
    write_dataset(file,
                  "level2/class key",
                  {hsize_t(class_key.size())},
                  class_key);
    for (unsigned int s = 0; s < 3; ++s)
      {
        const std::string stage = "level2/stage " + std::to_string(s + 1);
        write_dataset(file,
                      stage + "/table",
                      {hsize_t(table[s].size())},
                      table[s]);
        write_dataset(file,
                      stage + "/pairs",
                      {hsize_t(pairs[s].size() / 2), 2},
                      pairs[s]);
      }
    std::vector<std::int64_t> required_keys;
    for (const BlockKeys &block : required)
      required_keys.insert(required_keys.end(), block.begin(), block.end());
    write_dataset(file,
                  "level2/required",
                  {hsize_t(required.size()), 8},
                  required_keys);
    write_entries(file, "level2/entries", entries, 64, false);
  }



  bool
  Hierarchy::load(const std::int64_t file, const Database &level1)
  {
    const std::size_t n_level1_keys = level1.combinations().size();
    // Whether a valid level-1 key has a level-1 entry.
    const auto has_entry = [&level1](const std::int64_t key) {
      return level1.contains(level1.combinations().combination(key));
    };
    if (H5Lexists(file, "level2", H5P_DEFAULT) <= 0)
      return false;
    const std::string  text = read_attribute(file, "level 2 settings");
    std::istringstream in(text);
    std::string        word;
    char               comma;
    in >> word >> word >> settings.n_classes >> comma >> word >>
      settings.n_intermediate >> comma >> word >> settings.n_representatives >>
      comma >> word >> settings.regularization;
    // Files written before the second level had an offset of its own
    // name none. Their second level was fitted for the Gauss rule where
    // the first level's offset is the default; for another one, it was
    // fitted for a rule no longer used, and is dropped (builds fit it anew).
    // Files written before the second level had a sampler version name
    // none either (version 1); a level-2 build drops their fits and says
    // so (DatabaseBuilder::build(), HierarchySettings::fits_like()).
    const bool named_offset = bool(in >> comma);
    settings.point_offset   = solver::gauss_point_offset;
    if (named_offset)
      in >> word >> word >> settings.point_offset;
    const bool named_version = bool(in >> comma);
    settings.sampler_version = 1;
    if (named_version)
      in >> word >> word >> settings.sampler_version;
    std::string expected = settings.fingerprint();
    if (!named_version)
      expected.erase(expected.rfind(named_offset ? ", sampler version: " :
                                                   ", point offset: "));
    check(expected == text &&
            solver::valid_point_offset(settings.point_offset, 2),
          "has unreadable level-2 settings '" + text + "'");
    const unsigned int current = HierarchySettings().sampler_version;
    check(settings.sampler_version >= 1 && settings.sampler_version <= current,
          "has level-2 fits of sampler version " +
            std::to_string(settings.sampler_version) +
            ", this program knows versions 1 to " + std::to_string(current));
    if (!named_offset && level1.point_offset() != solver::gauss_point_offset)
      return false;

    class_of         = read_dataset<std::int32_t>(file,
                                          "level2/class of",
                                          {hsize_t(n_level1_keys)});
    const hsize_t n1 = dataset_length(file, "level2/class key");
    class_key = read_dataset<std::int64_t>(file, "level2/class key", {n1});
    // A class (c < n1) only for a combination with a level-1 entry, so
    // that covers() cannot take a class table for another file's entries.
    for (std::size_t k = 0; k < n_level1_keys; ++k)
      if (!(class_of[k] >= 0 && hsize_t(class_of[k]) <= n1 &&
            (hsize_t(class_of[k]) == n1 || has_entry(k))))
        check(false,
              "has an invalid level-2 class table (key " + std::to_string(k) +
                ": a class out of range, or one for a combination without "
                "a level-1 entry)");
    // A class key in its own class (which gives it a level-1 entry, as
    // checked above).
    for (hsize_t c = 0; c < n1; ++c)
      check(class_key[c] >= 0 && std::size_t(class_key[c]) < n_level1_keys &&
              hsize_t(class_of[class_key[c]]) == c,
            "has an invalid level-2 class key " + std::to_string(c) +
              " (no level-1 entry, or not in its own class)");
    hsize_t n_previous = n1;
    for (unsigned int s = 0; s < 3; ++s)
      {
        const std::string stage = "level2/stage " + std::to_string(s + 1);
        const hsize_t     n     = dataset_length(file, stage + "/pairs");
        table[s] =
          read_dataset<std::int32_t>(file,
                                     stage + "/table",
                                     {(n_previous + 1) * (n_previous + 1)});
        pairs[s] = read_dataset<std::int32_t>(file, stage + "/pairs", {n, 2});
        for (const auto c : pairs[s])
          check(c >= 0 && hsize_t(c) <= n_previous,
                "has invalid " + stage + " pairs");
        // As build_tables() makes them: a pair with a void half exists only
        // with void, the all-void pair (and only it, and the pairs that do
        // not exist) maps to void (n), and every representative to itself.
        const hsize_t m = n_previous + 1;
        for (hsize_t i = 0; i < table[s].size(); ++i)
          {
            const hsize_t a = i % m, b = i / m;
            const bool    exists =
              pair_exists(a, b, n_previous, level1.combinations().with_void());
            check(table[s][i] >= 0 && (exists ? hsize_t(table[s][i]) < n :
                                                hsize_t(table[s][i]) == n),
                  "has an invalid " + stage + " table (pair " +
                    std::to_string(i) +
                    ": a class out of range, a void pair with a class or a "
                    "pair of classes without one)");
          }
        for (hsize_t r = 0; r < n; ++r)
          check(table[s][pairs[s][2 * r] + m * pairs[s][2 * r + 1]] ==
                  std::int32_t(r),
                "has invalid " + stage + " pairs (representative " +
                  std::to_string(r) +
                  " is not in its own class, or is a pair that cannot "
                  "exist)");
        n_previous = n;
      }
    const hsize_t n_required = dataset_length(file, "level2/required");
    const std::vector<std::int64_t> required_keys =
      read_dataset<std::int64_t>(file, "level2/required", {n_required, 8});
    required.resize(n_required);
    for (hsize_t b = 0; b < n_required; ++b)
      for (unsigned int p = 0; p < 8; ++p)
        {
          required[b][p] = required_keys[8 * b + p];
          check(required[b][p] >= -1 &&
                  required[b][p] < std::int64_t(n_level1_keys) &&
                  (required[b][p] < 0 || has_entry(required[b][p])),
                "has an invalid level-2 required block " + std::to_string(b) +
                  " (a sub-block beyond the palette or with no level-1 "
                  "entry)");
        }
    check(std::is_sorted(required.begin(), required.end()),
          "has unsorted level-2 required blocks");
    entries = read_entries(file, "level2/entries", 64, false);
    for (const Entry &e : entries)
      check(e.key < n_previous, "has a level-2 entry beyond the tables");
    return true;
  }
} // namespace ddfem::coarsening
