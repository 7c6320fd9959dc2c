// The installer and the systemd unit: a dry run changes nothing, an install into a scratch root
// puts every file in place with the right modes and never overwrites a technician's config, and
// the installed unit passes `systemd-analyze verify` without a single warning.
#include <gtest/gtest.h>
#include <sys/stat.h>
#include <sys/wait.h>

#include <array>
#include <cstdio>
#include <regex>

#include "holo/core/files.hpp"
#include "shared_data.hpp"

namespace {

namespace fs = std::filesystem;

struct Result {
  int code;
  std::string output;  // stdout and stderr
};

Result run(const std::string& command) {
  Result r{-1, {}};
  FILE* pipe = popen((command + " 2>&1").c_str(), "r");
  if (!pipe) return r;
  std::array<char, 4096> buffer{};
  while (std::fgets(buffer.data(), buffer.size(), pipe)) r.output += buffer.data();
  const int status = pclose(pipe);
  r.code = WIFEXITED(status) ? WEXITSTATUS(status) : -1;
  return r;
}

const std::string kSource = HOLO_SOURCE_DIR;
const std::string kInstaller = kSource + "/scripts/install-kiosk";
const std::string kBuild = HOLO_BINARY_DIR;

unsigned mode(const fs::path& p) {
  struct stat st {};
  stat(p.c_str(), &st);
  return st.st_mode & 0777u;
}

TEST(InstallKiosk, DryRunPrintsEveryStepAndChangesNothing) {
  const auto root = holo::test::scratchDir("install_dry");
  const auto r = run(kInstaller + " --dry-run --build-dir " + kBuild + " --root " + root.string());
  ASSERT_EQ(r.code, 0) << r.output;
  EXPECT_NE(r.output.find("would run: install -D -m 0755"), std::string::npos) << r.output;
  EXPECT_NE(r.output.find("holopyramid.service"), std::string::npos) << r.output;
  EXPECT_NE(r.output.find("nothing was changed"), std::string::npos) << r.output;
  EXPECT_TRUE(fs::is_empty(root));
  // Against the real system (no --root) it plans the user and autostart, still changing nothing.
  const auto system = run(kInstaller + " --dry-run --build-dir " + kBuild);
  ASSERT_EQ(system.code, 0) << system.output;
  EXPECT_NE(system.output.find("would run: systemctl enable holopyramid.service"), std::string::npos)
      << system.output;
}

TEST(InstallKiosk, InstallsIntoARootAndKeepsAnExistingConfig) {
  const auto root = holo::test::scratchDir("install_root");
  auto r = run(kInstaller + " --build-dir " + kBuild + " --root " + root.string() + " --prefix /opt/holo");
  ASSERT_EQ(r.code, 0) << r.output;
  EXPECT_EQ(mode(root / "opt/holo/bin/holopyramid"), 0755u);
  EXPECT_EQ(mode(root / "etc/systemd/system/holopyramid.service"), 0644u);
  EXPECT_TRUE(fs::exists(root / "opt/holo/share/doc/holopyramid/kiosk.md"));
  for (const char* f : {"holopyramid-alerts.yml", "holopyramid-alerts.test.yml", "holopyramid-fleet.json"})
    EXPECT_EQ(mode(root / "opt/holo/share/doc/holopyramid/monitoring" / f), 0644u) << f;
  const std::string unit = holo::readFile(root / "etc/systemd/system/holopyramid.service");
  EXPECT_NE(unit.find("ExecStart=/opt/holo/bin/holopyramid kiosk"), std::string::npos);
  EXPECT_EQ(holo::readFile(root / "etc/holopyramid/holopyramid.yaml"),
            holo::readFile(kSource + "/packaging/holopyramid.yaml"));

  // A second install keeps the technician's edits and puts the default beside them.
  holo::writeFileAtomically(root / "etc/holopyramid/holopyramid.yaml", "kiosk: {max_fps: 12}\n");
  r = run(kInstaller + " --build-dir " + kBuild + " --root " + root.string() + " --prefix /opt/holo");
  ASSERT_EQ(r.code, 0) << r.output;
  EXPECT_EQ(holo::readFile(root / "etc/holopyramid/holopyramid.yaml"), "kiosk: {max_fps: 12}\n");
  EXPECT_TRUE(fs::exists(root / "etc/holopyramid/holopyramid.yaml.default"));
}

TEST(InstallKiosk, UnknownOptionIsRejected) {
  const auto r = run(kInstaller + " --frobnicate");
  EXPECT_EQ(r.code, 2);
  EXPECT_NE(r.output.find("--frobnicate"), std::string::npos) << r.output;
}

TEST(SystemdUnit, PassesSystemdAnalyzeVerifyWithoutWarnings) {
  if (run("command -v systemd-analyze").code != 0) GTEST_SKIP() << "systemd-analyze not installed";
  const auto root = holo::test::scratchDir("unit_verify");
  ASSERT_EQ(run(kInstaller + " --build-dir " + kBuild + " --root " + root.string()).code, 0);
  // verify checks that ExecStart exists: point it at the binary just installed in the root.
  std::string unit = holo::readFile(root / "etc/systemd/system/holopyramid.service");
  unit = std::regex_replace(unit, std::regex("ExecStart=/usr/local/bin/holopyramid"),
                            "ExecStart=" + (root / "usr/local/bin/holopyramid").string());
  EXPECT_NE(unit.find("Type=notify"), std::string::npos);
  EXPECT_NE(unit.find("WatchdogSec="), std::string::npos);
  EXPECT_NE(unit.find("Restart=always"), std::string::npos);
  holo::writeFileAtomically(root / "holopyramid.service", unit);
  const auto r = run("systemd-analyze verify " + (root / "holopyramid.service").string());
  EXPECT_EQ(r.code, 0) << r.output;
  EXPECT_EQ(r.output, "") << "systemd-analyze verify warned";
  // A misspelt key must make it warn (so the empty output above means something).
  holo::writeFileAtomically(root / "bad.service",
                            std::regex_replace(unit, std::regex("WatchdogSec"), "WatchdgSec"));
  EXPECT_NE(run("systemd-analyze verify " + (root / "bad.service").string()).output.find("WatchdgSec"),
            std::string::npos);
}

// The sandbox: `systemd-analyze security` rates the unit's exposure (0 = locked down, 10 = none);
// the kiosk needs the cameras, the GPU and the loopback endpoint, and nothing else it flags.
TEST(SystemdUnit, SandboxExposureStaysLow) {
  if (run("command -v systemd-analyze").code != 0) GTEST_SKIP() << "systemd-analyze not installed";
  const std::string unit = kSource + "/packaging/holopyramid.service";
  const auto r = run("systemd-analyze security --offline=yes --no-pager " + unit);
  std::smatch match;
  ASSERT_TRUE(
      std::regex_search(r.output, match, std::regex("exposure level for holopyramid.service: ([0-9.]+)")))
      << r.output;
  EXPECT_LE(std::stod(match[1].str()), 1.5) << r.output;
  const std::string text = holo::readFile(unit);
  EXPECT_NE(text.find("SystemCallFilter=@system-service"), std::string::npos);
  EXPECT_NE(text.find("SystemCallErrorNumber=EPERM"), std::string::npos);  // a missed call fails, never kills
  EXPECT_NE(text.find("IPAddressDeny=any"), std::string::npos);
}

}  // namespace
