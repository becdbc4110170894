#include <gtest/gtest.h>

#include "render_fixture.h"

int main(int argc, char** argv) {
    ::testing::InitGoogleTest(&argc, argv);
    ::testing::AddGlobalTestEnvironment(new pnb::player::test::HeadlessEnvironment);
    return RUN_ALL_TESTS();
}
