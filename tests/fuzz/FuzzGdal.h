#pragma once
// For the targets that go through GDAL: every driver registered once, before the first input,
// and GDAL's own messages kept quiet (a target judges what Orbis returns, not what GDAL says).
// Include it in the target's one source file: it defines libFuzzer's initialisation hook.

#include <cpl_error.h>
#include <gdal.h>

extern "C" int LLVMFuzzerInitialize(int*, char***) {
    GDALAllRegister();
    CPLSetErrorHandler(CPLQuietErrorHandler);
    return 0;
}
