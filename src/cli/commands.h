#pragma once
/// The subcommands of the rayproof tool. Each `add_*` registers its options on the CLI11 app and
/// returns the function to run when that subcommand was chosen (its exit status).
#include <functional>

namespace CLI { class App; }

namespace rayproof::cli {

using Run = std::function<int()>;

Run add_classify(CLI::App& app);
Run add_gen(CLI::App& app);
Run add_verify(CLI::App& app);
Run add_report(CLI::App& app);
Run add_fuzz(CLI::App& app);
Run add_cast(CLI::App& app);
Run add_render(CLI::App& app);
Run add_bench(CLI::App& app);
Run add_check(CLI::App& app);
Run add_serve(CLI::App& app);
Run add_plugin_host(CLI::App& app);
Run add_opencl_host(CLI::App& app);
Run add_glsl_host(CLI::App& app);
Run add_irradiance(CLI::App& app);
Run add_spawn(CLI::App& app);
Run add_advise(CLI::App& app);
Run add_contains(CLI::App& app);
/// `rayproof bench contains`: registered on the bench subcommand; main runs it before bench.
Run add_bench_contains(CLI::App& bench);
/// `rayproof bench crossings`: registered on the bench subcommand; main runs it before bench.
Run add_bench_crossings(CLI::App& bench);
/// `rayproof distance`: closest points and distances (rayproof/scene/distance.h).
Run add_distance(CLI::App& app);
/// `rayproof bench distance`: registered on the bench subcommand; main runs it before bench.
Run add_bench_distance(CLI::App& bench);
/// `rayproof bench intersect`: registered on the bench subcommand; main runs it before bench.
Run add_bench_intersect(CLI::App& bench);
/// `rayproof intersect`: self-intersections and contact pairs (rayproof/scene/intersections.h).
Run add_intersect(CLI::App& app);

}  // namespace rayproof::cli
