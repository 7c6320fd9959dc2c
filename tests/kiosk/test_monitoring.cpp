// The fleet's monitoring shipped in packaging/: the Prometheus alert rules and the Grafana
// dashboard. Both name the kiosk's metrics by hand, so a renamed or dropped metric would leave an
// alert that never fires and a panel that stays empty; these tests hold them to what
// HealthStatus::toPrometheus exports, and check every query with Debian's promtool.
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>
#include <regex>
#include <set>
#include <sstream>
#include <string>

#include "holo/kiosk/health_status.hpp"
#include "run_command.hpp"

namespace holo::kiosk {
namespace {

const std::filesystem::path kPackaging = std::filesystem::path(HOLO_SOURCE_DIR) / "packaging";
const std::filesystem::path kRules = kPackaging / "prometheus" / "holopyramid-alerts.yml";
const std::filesystem::path kDashboard = kPackaging / "grafana" / "holopyramid-fleet.json";

std::string readText(const std::filesystem::path& path) {
  std::ifstream in(path);
  EXPECT_TRUE(in) << "cannot read " << path;
  std::stringstream text;
  text << in.rdbuf();
  return text.str();
}

// Every figure present, so that every metric family the kiosk can export is in the text.
HealthStatus fullStatus() {
  HealthStatus h;
  h.state = "running";
  h.fps = 25;
  h.frame_ms = 31;
  h.frame_budget_ms = 40;
  h.target_fps = 25;
  h.stage_ms = {{"reflections", 20.0}};
  h.foreground_share = 0.1;
  h.camera_skew_ms = 4.0;
  CameraHealth camera;
  camera.name = "face0";
  camera.alive = true;
  camera.unpaired = 1;
  camera.pair_skew_ms = 2.0;
  h.cameras = {camera};
  h.exhibit_problems = {"entry 2 (amphora): missing file"};
  return h;
}

std::set<std::string> exportedMetrics() {
  std::set<std::string> names;
  std::istringstream lines(fullStatus().toPrometheus());
  for (std::string line; std::getline(lines, line);) {
    if (line.empty() || line[0] == '#') continue;
    names.insert(line.substr(0, line.find_first_of("{ ")));
  }
  return names;
}

std::set<std::string> namedMetrics(const std::string& text) {
  std::set<std::string> names;
  const std::regex metric(R"(\bholopyramid_[a-z_]+)");
  for (auto it = std::sregex_iterator(text.begin(), text.end(), metric); it != std::sregex_iterator(); ++it)
    names.insert(it->str());
  return names;
}

// The dashboard's queries with its variables replaced as Grafana would for "all pyramids".
std::vector<std::string> dashboardQueries(const nlohmann::json& dashboard) {
  std::vector<std::string> queries;
  for (const auto& panel : dashboard.at("panels")) {
    if (panel.at("type") == "row") continue;
    for (const auto& target : panel.at("targets")) {
      std::string expr = target.at("expr").get<std::string>();
      expr = std::regex_replace(expr, std::regex(R"(\$instance)"), ".*");
      queries.push_back(expr);
    }
  }
  return queries;
}

std::string promtool() {
  const std::string path = HOLO_PROMTOOL;
  if (path.empty() || !std::filesystem::exists(path))
    ADD_FAILURE() << "promtool not found: scripts/install-deps installs it (Debian package prometheus)";
  return path;
}

TEST(Monitoring, EveryMetricTheAlertRulesNameIsExported) {
  const std::set<std::string> exported = exportedMetrics();
  const std::set<std::string> named = namedMetrics(readText(kRules));
  EXPECT_GE(named.size(), 8u);
  for (const auto& name : named) EXPECT_TRUE(exported.count(name)) << kRules << " names " << name;
}

TEST(Monitoring, EveryMetricTheDashboardNamesIsExported) {
  const std::set<std::string> exported = exportedMetrics();
  const std::set<std::string> named = namedMetrics(readText(kDashboard));
  EXPECT_GE(named.size(), 15u);
  for (const auto& name : named) EXPECT_TRUE(exported.count(name)) << kDashboard << " names " << name;
}

TEST(Monitoring, TheMetricCheckSeesARenamedMetric) {
  // The adversary: a rule naming a metric the kiosk does not export must be caught.
  const std::set<std::string> exported = exportedMetrics();
  EXPECT_FALSE(exported.count("holopyramid_frame_rate"));
  EXPECT_TRUE(namedMetrics("expr: holopyramid_frame_rate < 20").count("holopyramid_frame_rate"));
}

TEST(Monitoring, TheDashboardLoadsAndItsPanelsDoNotOverlap) {
  const nlohmann::json dashboard = nlohmann::json::parse(readText(kDashboard));
  EXPECT_EQ(dashboard.at("uid"), "holopyramid-fleet");
  // Many appliances: an `instance` variable with multi-select and "All" filters every panel.
  bool instance_variable = false;
  for (const auto& variable : dashboard.at("templating").at("list"))
    if (variable.at("name") == "instance")
      instance_variable = variable.at("multi").get<bool>() && variable.at("includeAll").get<bool>();
  EXPECT_TRUE(instance_variable);
  std::set<int> ids;
  struct Box {
    int x, y, w, h;
  };
  std::vector<Box> boxes;
  for (const auto& panel : dashboard.at("panels")) {
    EXPECT_TRUE(ids.insert(panel.at("id").get<int>()).second) << "duplicate panel id " << panel.at("id");
    const auto& g = panel.at("gridPos");
    const Box box{g.at("x"), g.at("y"), g.at("w"), g.at("h")};
    EXPECT_LE(box.x + box.w, 24) << panel.at("title");
    for (const Box& other : boxes) {
      const bool apart = box.x + box.w <= other.x || other.x + other.w <= box.x || box.y + box.h <= other.y ||
                         other.y + other.h <= box.y;
      EXPECT_TRUE(apart) << panel.at("title") << " overlaps another panel";
    }
    boxes.push_back(box);
    if (panel.at("type") == "row") continue;
    EXPECT_EQ(panel.at("datasource").at("uid"), "${datasource}") << panel.at("title");
    EXPECT_FALSE(panel.at("targets").empty()) << panel.at("title");
    for (const auto& target : panel.at("targets"))
      EXPECT_NE(target.at("expr").get<std::string>().find("$instance"), std::string::npos)
          << panel.at("title") << ": a query that ignores the pyramid selection";
  }
}

TEST(Monitoring, TheAlertRulesPassPromtoolAndTheirUnitTests) {
  const std::string tool = promtool();
  const auto log = std::filesystem::temp_directory_path() / "holo_promtool_rules.log";
  EXPECT_EQ(test::runCommand(tool + " check rules " + kRules.string(), log), 0) << readText(log);
  const auto tests = kPackaging / "prometheus" / "holopyramid-alerts.test.yml";
  EXPECT_EQ(test::runCommand("cd " + tests.parent_path().string() + " && " + tool + " test rules " +
                                 tests.filename().string(),
                             log),
            0)
      << readText(log);
}

TEST(Monitoring, EveryDashboardQueryIsValidPromQL) {
  // promtool checks expressions inside rule files: each query becomes a recording rule.
  const std::string tool = promtool();
  const auto dir = std::filesystem::temp_directory_path() / "holo_dashboard_queries";
  std::filesystem::create_directories(dir);
  const std::vector<std::string> queries = dashboardQueries(nlohmann::json::parse(readText(kDashboard)));
  ASSERT_GE(queries.size(), 15u);
  std::ostringstream yaml;
  yaml << "groups:\n  - name: dashboard\n    rules:\n";
  for (std::size_t i = 0; i < queries.size(); ++i)
    yaml << "      - record: dashboard_query_" << i << "\n        expr: " << nlohmann::json(queries[i]).dump()
         << "\n";
  std::ofstream(dir / "queries.yml") << yaml.str();
  const auto log = dir / "promtool.log";
  EXPECT_EQ(test::runCommand(tool + " check rules " + (dir / "queries.yml").string(), log), 0)
      << readText(log);
  // The adversary: a broken query must fail the same check.
  std::ofstream(dir / "broken.yml") << "groups:\n  - name: dashboard\n    rules:\n      - record: broken\n"
                                       "        expr: \"sum(holopyramid_frames_per_second\"\n";
  EXPECT_NE(test::runCommand(tool + " check rules " + (dir / "broken.yml").string(), log), 0);
}

TEST(Monitoring, TheExpositionPassesPromtoolsLint) {
  const std::string tool = promtool();
  const auto dir = std::filesystem::temp_directory_path();
  std::ofstream(dir / "holo_metrics.txt") << fullStatus().toPrometheus();
  const auto log = dir / "holo_promtool_metrics.log";
  EXPECT_EQ(test::runCommand(tool + " check metrics < " + (dir / "holo_metrics.txt").string(), log), 0)
      << readText(log);
}

}  // namespace
}  // namespace holo::kiosk
