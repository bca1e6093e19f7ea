// C3 conditioning sweep (verification.md section 4): the C2 column on an interface layer with
// k_n h / E from 1 to 1e8 for every interface element kind; prints condition number, Newton
// iterations and the errors of the top settlement and of the interface closure as a Markdown
// table (docs/contact.md). Run: build/release/bin/contact_conditioning
#include "../../tests/contact_scenes.hpp"

#include <cstdio>
#include <utility>
#include <vector>

int main() {
  using namespace stratum::testing;
  std::printf("| element | nodes | k_n h/E | cond(K) | Newton its | error of w | error of q/k_n |\n");
  std::printf("|---|---|---|---|---|---|---|\n");
  for (int npc : {4, 8})
    for (const char* kind : {"contact2", "interface_line", "interface_line_gauss", "thin_layer"})
      for (double ratio : {1.0, 1e2, 1e4, 1e6, 1e8}) {
        const auto r = conditioning(kind, ratio, npc, STRATUM_PLUGIN_DIR);
        std::printf("| %s | %d | %.0e | %.2e | %d | %.1e | %.1e |%s\n", kind, npc, ratio, r.cond,
                    r.iterations, r.error, r.interface_error, r.ok ? "" : " (failed)");
      }
  // C1: the rigid pile, P(w) against Randolph & Wroth before slip and the shaft capacity after.
  std::printf("\n| element | P/P_RW at w = w_s/4 | at w_s/2 | at 3 w_s/4 | P_end / (2 pi r L tau_max) |\n");
  std::printf("|---|---|---|---|---|\n");
  for (const char* kind : {"contact2", "interface_line", "thin_layer"}) {
    PileSpec s;
    s.kind = kind;
    std::vector<std::pair<double, double>> curve;
    stratum::RunOptions o;
    o.plugin_dirs = {STRATUM_PLUGIN_DIR};
    o.write_output = false;
    stratum::Analysis* self = nullptr;
    o.on_step = [&](int, int, double lambda, const stratum::StepReport&) {
      curve.emplace_back(lambda * s.w_max(), pile_load(self->model(), s));
    };
    auto a = stratum::Analysis::from_string(pile_scene(s), "pile.toml", o);
    self = a.get();
    if (!a->run().outcome.ok() || curve.size() < 12) {
      std::printf("| %s | failed |\n", kind);
      continue;
    }
    // Steps of w_max / 12 = w_s / 4.
    auto ratio = [&](int i) {
      return curve[static_cast<std::size_t>(i)].second /
             (s.shaft_stiffness() * curve[static_cast<std::size_t>(i)].first);
    };
    std::printf("| %s | %.4f | %.4f | %.4f | %.5f |\n", kind, ratio(0), ratio(1), ratio(2),
                curve.back().second / s.shaft_capacity());
  }
  return 0;
}
