// tests/support/cli_fixture.h — a GoogleTest fixture for tests that run the certray executable:
// a fresh temporary directory per test, files written into it, and `certray ARGS` run there with
// its exit code, stdout and stderr captured. The test target defines CERTRAY_CLI (the binary).
#pragma once

#include <gtest/gtest.h>
#include <sys/wait.h>

#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>

#ifndef CERTRAY_CLI
#error "CERTRAY_CLI must name the certray executable"
#endif

namespace certray::testing {

/// The whole file as a string (empty if it cannot be read).
inline std::string slurp(const std::filesystem::path& p) {
    std::ifstream in(p, std::ios::binary);
    std::stringstream ss;
    ss << in.rdbuf();
    return ss.str();
}

class CliFixture : public ::testing::Test {
  protected:
    void SetUp() override {
        std::string tmpl = (std::filesystem::temp_directory_path() / "certray_cli_XXXXXX").string();
        ASSERT_NE(mkdtemp(tmpl.data()), nullptr);
        dir_ = tmpl;
    }
    void TearDown() override {
        std::error_code ec;
        std::filesystem::remove_all(dir_, ec);
    }

    std::filesystem::path path(const std::string& name) const { return dir_ / name; }
    void write(const std::string& name, const std::string& text) const {
        std::ofstream(path(name), std::ios::binary) << text;
    }

    /// Runs `certray ARGS` in the temporary directory; returns the exit code (−1 if it did not
    /// exit normally), with stdout in out_ and stderr in err_ (kept in stdout.txt, stderr.txt).
    int run(const std::string& args) {
        const std::string cmd = "cd '" + dir_.string() + "' && '" CERTRAY_CLI "' " + args + " > '" +
                                path("stdout.txt").string() + "' 2> '" +
                                path("stderr.txt").string() + "'";
        const int status = std::system(cmd.c_str());
        out_ = slurp(path("stdout.txt"));
        err_ = slurp(path("stderr.txt"));
        if (status == -1 || !WIFEXITED(status)) return -1;
        return WEXITSTATUS(status);
    }

    std::filesystem::path dir_;
    std::string out_, err_;
};

}  // namespace certray::testing
