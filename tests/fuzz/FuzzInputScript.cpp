// Recorded input scripts for the viewer (ui/InputScript.h), read from a file as the viewer does.
#include "tests/fuzz/FuzzInput.h"
#include "ui/InputScript.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
    orbis::fuzz::MemoryFile file(data, size);
    if (file.ok()) (void)orbis::ui::readInputScript(file.path());
    return 0;
}
