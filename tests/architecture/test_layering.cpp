// The layering the architecture promises, checked on the source tree and on the link graph CMake
// resolved (architecture/modules.txt in the build folder, written by the top CMakeLists.txt):
//  * a module's files include only headers of the modules its libraries link;
//  * the live product's modules link no simulation, reference renderer, evaluation or command line;
//  * inside a module no two components include each other, directly or round a cycle (a
//    component is a header with its source of the same name): such a back arrow is what a pass
//    including its orchestrator for a type is.
#include <gtest/gtest.h>

#include <algorithm>
#include <filesystem>
#include <fstream>
#include <functional>
#include <map>
#include <regex>
#include <set>
#include <sstream>
#include <string>
#include <vector>

namespace fs = std::filesystem;

namespace {

using ModuleSet = std::set<std::string>;

// modules.txt: one line per module folder, "FOLDER: LINKED FOLDER ...", every folder whose
// libraries the folder's libraries link, directly or through others.
std::map<std::string, ModuleSet> linkedModules() {
  const fs::path path = fs::path(HOLO_BINARY_DIR) / "architecture" / "modules.txt";
  std::ifstream in(path);
  EXPECT_TRUE(in) << path << " is missing: the top CMakeLists.txt writes it at configure time";
  std::map<std::string, ModuleSet> modules;
  std::string line;
  while (std::getline(in, line)) {
    std::istringstream words(line);
    std::string folder;
    words >> folder;
    if (folder.empty()) continue;
    folder.pop_back();  // the colon
    ModuleSet& linked = modules[folder];
    for (std::string dep; words >> dep;) linked.insert(dep);
  }
  return modules;
}

std::vector<fs::path> sourcesOf(const std::string& module) {
  std::vector<fs::path> files;
  const fs::path root = fs::path(HOLO_SOURCE_DIR) / module;
  for (const auto& entry : fs::recursive_directory_iterator(root)) {
    const std::string ext = entry.path().extension().string();
    if (entry.is_regular_file() && (ext == ".hpp" || ext == ".cpp")) files.push_back(entry.path());
  }
  std::sort(files.begin(), files.end());
  return files;
}

// The project's includes of a file: "holo/MODULE/NAME.hpp" as (MODULE, NAME) and a quoted local
// "NAME.hpp" as ("", NAME).
std::vector<std::pair<std::string, std::string>> includesOf(const fs::path& file) {
  static const std::regex project(R"re(^\s*#\s*include\s*"holo/([a-z_]+)/([A-Za-z0-9_]+)\.hpp")re");
  static const std::regex local(R"re(^\s*#\s*include\s*"([A-Za-z0-9_]+)\.hpp")re");
  std::vector<std::pair<std::string, std::string>> includes;
  std::ifstream in(file);
  std::smatch m;
  for (std::string line; std::getline(in, line);) {
    if (std::regex_search(line, m, project))
      includes.emplace_back(m[1], m[2]);
    else if (std::regex_search(line, m, local))
      includes.emplace_back("", m[1]);
  }
  return includes;
}

std::string sourcePath(const fs::path& file) {
  return fs::relative(file, HOLO_SOURCE_DIR).string();
}

TEST(Layering, EveryModuleIncludesOnlyTheModulesItLinks) {
  const auto modules = linkedModules();
  ASSERT_GE(modules.size(), 10u);
  for (const auto& [module, linked] : modules) {
    for (const fs::path& file : sourcesOf(module)) {
      for (const auto& [included, name] : includesOf(file)) {
        if (included.empty() || included == module) continue;
        EXPECT_TRUE(linked.count(included) != 0)
            << sourcePath(file) << " includes holo/" << included << "/" << name << ".hpp but " << module
            << " does not link " << included;
      }
    }
  }
}

TEST(Layering, TheLiveProductLinksNoSimulationNoReferenceAndNoMeasurement) {
  const auto modules = linkedModules();
  const ModuleSet product = {"core",    "capture", "depthfilter", "reflect", "ar",
                             "display", "calib",   "kiosk",       "pipeline"};
  const ModuleSet apart = {"sim", "reference", "simulated", "eval"};
  for (const std::string& module : product) {
    ASSERT_TRUE(modules.count(module)) << module << " is not in modules.txt";
    for (const std::string& other : modules.at(module))
      EXPECT_FALSE(apart.count(other)) << "the live product's " << module << " links " << other;
  }
}

// Tarjan's strongly connected components over the module's components; a component of more than
// one name is a cycle.
std::vector<std::vector<std::string>> cyclesIn(const std::map<std::string, std::set<std::string>>& graph) {
  std::map<std::string, int> index, low;
  std::set<std::string> on_stack;
  std::vector<std::string> stack;
  std::vector<std::vector<std::string>> cycles;
  int next = 0;
  std::function<void(const std::string&)> visit = [&](const std::string& v) {
    index[v] = low[v] = next++;
    stack.push_back(v);
    on_stack.insert(v);
    const auto edges = graph.find(v);
    if (edges != graph.end()) {
      for (const std::string& w : edges->second) {
        if (!graph.count(w)) continue;
        if (!index.count(w)) {
          visit(w);
          low[v] = std::min(low[v], low[w]);
        } else if (on_stack.count(w)) {
          low[v] = std::min(low[v], index[w]);
        }
      }
    }
    if (low[v] != index[v]) return;
    std::vector<std::string> component;
    std::string w;
    do {
      w = stack.back();
      stack.pop_back();
      on_stack.erase(w);
      component.push_back(w);
    } while (w != v);
    if (component.size() > 1) cycles.push_back(component);
  };
  for (const auto& [v, edges] : graph)
    if (!index.count(v)) visit(v);
  return cycles;
}

TEST(Layering, NoComponentOfAModuleIncludesOneThatIncludesItBack) {
  for (const auto& [module, linked] : linkedModules()) {
    std::map<std::string, std::set<std::string>> graph;
    for (const fs::path& file : sourcesOf(module)) {
      const std::string component = file.stem().string();
      auto& edges = graph[component];
      for (const auto& [included, name] : includesOf(file))
        if ((included.empty() || included == module) && name != component) edges.insert(name);
    }
    for (const auto& cycle : cyclesIn(graph)) {
      std::string names;
      for (const std::string& c : cycle) names += " " + c;
      ADD_FAILURE() << module << ": these components include each other round a cycle:" << names;
    }
  }
}

TEST(Layering, TheCycleCheckFindsABackArrow) {
  const std::map<std::string, std::set<std::string>> orchestrated = {
      {"frame_renderer", {"refraction_pass", "tracer_settings"}},
      {"refraction_pass", {"tracer_settings"}},
      {"tracer_settings", {}}};
  EXPECT_TRUE(cyclesIn(orchestrated).empty());
  auto back = orchestrated;
  back["refraction_pass"].insert("frame_renderer");
  const auto cycles = cyclesIn(back);
  ASSERT_EQ(cycles.size(), 1u);
  EXPECT_EQ(cycles[0].size(), 2u);
}

}  // namespace
