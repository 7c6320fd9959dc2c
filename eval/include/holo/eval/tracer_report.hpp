// The reports of the nine-scene tracer evaluation (`holopyramid eval tracer`,
// tracer_evaluation.hpp): the Markdown tables (fg_mse in the paper's Table 1 units with the
// ratios to ours, the times, the glass relics), the bars of acceptance_bars.hpp one line each with
// the worst scene, and the files results.csv, results.json, table.md and plot.svg (fg_mse against
// the time per view, log-log).
#pragma once

#include <filesystem>
#include <ostream>
#include <string>
#include <vector>

#include "holo/eval/tracer_evaluation.hpp"

namespace holo::eval {

std::string tracerMarkdownTable(const std::vector<SceneResult>& results, const TracerEvalOptions& options);

// Writes one line per bar to `out`; returns whether the fg_mse bars against ibl and ssrt hold on
// every scene with a foreground region.
bool reportTracerBars(const std::vector<SceneResult>& results, std::ostream& out);

// Into `dir` (created): results.csv, results.json, table.md (`table`, then `bars`) and plot.svg.
void writeTracerResults(const std::vector<SceneResult>& results, const TracerEvalOptions& options,
                        const std::filesystem::path& dir, const std::string& table, const std::string& bars);

}  // namespace holo::eval
