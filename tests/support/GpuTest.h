#pragma once
// Base for GPU tests: lavapipe selected explicitly (so results are the same on any machine),
// the Khronos validation layer on, and any validation message fails the test.

#include "engine/gpu/Device.h"
#include "engine/gpu/Instance.h"

#include <gtest/gtest.h>

#include <memory>

namespace orbis::test {

/// Points the Vulkan loader at Mesa's lavapipe only. Call before the first Vulkan call (the
/// test main does). Returns false when lavapipe's ICD file is not installed.
bool selectLavapipe();

class GpuTest : public ::testing::Test {
protected:
    static void SetUpTestSuite();
    static void TearDownTestSuite();
    void SetUp() override;
    void TearDown() override;

    /// For tests that provoke validation on purpose: messages so far are expected, not failures.
    void acknowledgeValidationMessages();

    static gpu::Instance& instance() { return *instance_; }
    static gpu::Device& device() { return *device_; }

private:
    static std::unique_ptr<gpu::Instance> instance_;
    static std::unique_ptr<gpu::Device> device_;
    static int acknowledged_;
    int messagesAtStart_ = 0;
};

/// Threads of this process right now (from /proc/self/task).
int processThreadCount();

}  // namespace orbis::test
