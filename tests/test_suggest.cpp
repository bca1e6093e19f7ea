// "Did you mean": the edit distance against hand-counted values and the closeness rule.
#include "suggest.hpp"

#include <catch2/catch.hpp>

#include <map>
#include <string>
#include <vector>

namespace test_suggest {

using stratum::closest_name;
using stratum::did_you_mean;
using stratum::edit_distance;

TEST_CASE("suggest: restricted Damerau-Levenshtein distance", "[suggest]") {
  CHECK(edit_distance("", "") == 0);
  CHECK(edit_distance("", "abc") == 3);
  CHECK(edit_distance("kitten", "sitting") == 3); // k->s, e->i, +g
  CHECK(edit_distance("nuu", "nu") == 1);
  CHECK(edit_distance("sigma_yy", "sigma_y") == 1);
  CHECK(edit_distance("ring.lfet", "ring.left") == 1); // one transposition
  CHECK(edit_distance("ca", "abc") == 3);  // optimal string alignment: no edit of a transposed pair
  CHECK(edit_distance("Phi", "phi") == 0); // letters compare case-insensitively
}

TEST_CASE("suggest: only close names are suggested", "[suggest]") {
  const std::vector<std::string_view> keys{"E", "nu", "sigma_y", "H", "phi", "psi"};
  CHECK(closest_name("nuu", keys) == "nu");
  CHECK(closest_name("sigma_yy", keys) == "sigma_y");
  CHECK(closest_name("sigmay", keys) == "sigma_y");
  CHECK(closest_name("e", keys) == "E");
  CHECK(closest_name("porosity", keys).empty());
  CHECK(closest_name("xy", keys).empty()); // two edits in a two-letter name is not a misspelling
  CHECK(closest_name("nu", keys).empty()); // a known name needs no suggestion
  CHECK(did_you_mean("phii", keys) == "; did you mean 'phi'?");
  CHECK(did_you_mean("porosity", keys).empty());
  // Ties go to the first candidate: "pxi" is one edit from both phi and psi.
  CHECK(closest_name("pxi", keys) == "phi");
  const std::map<std::string, int> sets{{"near_shaft", 1}, {"pile_below", 2}};
  CHECK(did_you_mean("near_shafts", sets) == "; did you mean 'near_shaft'?");
  CHECK(did_you_mean("pile_belo", std::vector<std::string>{"pile_below"}) == "; did you mean 'pile_below'?");
}

} // namespace test_suggest
