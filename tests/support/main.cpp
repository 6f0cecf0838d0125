// tests/support/main.cpp — the test main: GoogleTest, with the rounding mode checked after every
// test.
#include <gtest/gtest.h>

#include <cfenv>

namespace {

/// Fails the test that leaves the floating-point rounding mode changed (a leaked RoundingScope).
class RoundingModeListener : public testing::EmptyTestEventListener {
    void OnTestStart(const testing::TestInfo&) override { mode_ = std::fegetround(); }
    void OnTestEnd(const testing::TestInfo& info) override {
        if (std::fegetround() != mode_) {
            std::fesetround(mode_);
            ADD_FAILURE() << info.name() << " left the rounding mode changed";
        }
    }
    int mode_ = FE_TONEAREST;
};

}  // namespace

int main(int argc, char** argv) {
    testing::InitGoogleTest(&argc, argv);
    testing::UnitTest::GetInstance()->listeners().Append(new RoundingModeListener);
    return RUN_ALL_TESTS();
}
