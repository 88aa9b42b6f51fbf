// main() for GPU tests: select lavapipe before anything touches the Vulkan loader.
#include "tests/support/GpuTest.h"

#include <gtest/gtest.h>

int main(int argc, char** argv) {
    orbis::test::selectLavapipe();
    ::testing::InitGoogleTest(&argc, argv);
    return RUN_ALL_TESTS();
}
