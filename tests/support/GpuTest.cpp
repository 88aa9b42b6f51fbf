#include "tests/support/GpuTest.h"

#include <cstdlib>
#include <filesystem>

namespace orbis::test {

std::unique_ptr<gpu::Instance> GpuTest::instance_;
std::unique_ptr<gpu::Device> GpuTest::device_;
int GpuTest::acknowledged_ = 0;

void GpuTest::acknowledgeValidationMessages() {
    acknowledged_ += instance_->validationMessages() - messagesAtStart_;
    messagesAtStart_ = instance_->validationMessages();
}

bool selectLavapipe() {
    namespace fs = std::filesystem;
    std::error_code ec;
    for (const char* dir : {"/usr/share/vulkan/icd.d", "/etc/vulkan/icd.d", "/usr/local/share/vulkan/icd.d"}) {
        for (const auto& entry : fs::directory_iterator(dir, ec)) {
            const std::string name = entry.path().filename().string();
            if (name.rfind("lvp_icd", 0) == 0 && entry.path().extension() == ".json") {
                setenv("VK_ICD_FILENAMES", entry.path().c_str(), 1);
                setenv("VK_DRIVER_FILES", entry.path().c_str(), 1);
                if (!std::getenv("XDG_RUNTIME_DIR")) {
                    const fs::path runtime = fs::temp_directory_path() / "orbis-test-runtime";
                    fs::create_directories(runtime, ec);
                    setenv("XDG_RUNTIME_DIR", runtime.c_str(), 1);
                }
                return true;
            }
        }
    }
    return false;
}

void GpuTest::SetUpTestSuite() {
    if (instance_) return;
    ASSERT_TRUE(selectLavapipe()) << "lavapipe's ICD (lvp_icd.*.json) is not installed: run tools/install-deps.sh";
    gpu::InstanceOptions io;
    io.validation = true;
    instance_ = std::make_unique<gpu::Instance>(io);
    gpu::DeviceOptions dopt;
    dopt.select = "llvmpipe";
    device_ = std::make_unique<gpu::Device>(*instance_, dopt);
}

void GpuTest::TearDownTestSuite() {
    device_.reset();
    const int messages = instance_ ? instance_->validationMessages() - acknowledged_ : 0;
    const std::string first = instance_ ? instance_->firstValidationMessage() : std::string();
    instance_.reset();
    acknowledged_ = 0;
    // Destroying the device can itself report (leaked objects): check after it.
    EXPECT_EQ(messages, 0) << "validation at device destruction: " << first;
}

void GpuTest::SetUp() {
    ASSERT_TRUE(device_) << "no Vulkan device";
    messagesAtStart_ = instance_->validationMessages();
}

void GpuTest::TearDown() {
    device_->waitIdle();
    EXPECT_EQ(instance_->validationMessages(), messagesAtStart_)
        << "validation message(s); first of the run: " << instance_->firstValidationMessage();
}

int processThreadCount() {
    int n = 0;
    std::error_code ec;
    for (const auto& e : std::filesystem::directory_iterator("/proc/self/task", ec)) {
        (void)e;
        ++n;
    }
    return n;
}

}  // namespace orbis::test
