// tests/support/main.cpp — the test main: GoogleTest, with the floating-point control words
// checked after every test, and an optional host floating-point state for the whole run.
//
// CERTRAY_HOST_FPENV=ftz-daz|upward|downward|toward-zero makes the tests call the library as a
// host in that state would (testing::as_host, tests/support/fp_env.h): the answers must be those
// of the default state, since the library owns the environment inside its own scopes
// (interval/interval.h).
#include <gtest/gtest.h>

#include <cstdio>
#include <cstdlib>
#include <string>

#include "tests/support/fp_env.h"

namespace {

using certray::testing::FpWords;

/// Fails the test that leaves the MXCSR or x87 control word changed (a leaked scope). MXCSR's six
/// sticky exception flags (bits 0-5) are status, raised by any inexact operation, not control.
class FpWordsListener : public testing::EmptyTestEventListener {
    void OnTestStart(const testing::TestInfo&) override {
        words_ = certray::testing::read_fp_words();
    }
    void OnTestEnd(const testing::TestInfo& info) override {
        const FpWords now = certray::testing::read_fp_words();
        if (!same_control(now, words_)) {
            certray::testing::write_fp_words(words_);
            ADD_FAILURE() << info.name() << " left the floating-point control words changed: "
                          << certray::testing::describe(words_) << " -> "
                          << certray::testing::describe(now);
        }
    }
    FpWords words_;
};

}  // namespace

int main(int argc, char** argv) {
    testing::InitGoogleTest(&argc, argv);
    if (const char* host = std::getenv("CERTRAY_HOST_FPENV")) {
        FpWords w;
        if (!certray::testing::host_fp_words(host, certray::testing::read_fp_words(), w)) {
            std::fprintf(stderr, "CERTRAY_HOST_FPENV: unknown state '%s'\n", host);
            return 2;
        }
        std::fprintf(stderr, "library calls made as a host in state '%s': %s\n", host,
                     certray::testing::describe(w).c_str());
    }
    testing::UnitTest::GetInstance()->listeners().Append(new FpWordsListener);
    return RUN_ALL_TESTS();
}
