#pragma once
// For the targets that go through GDAL: every driver registered once, before the first input,
// and GDAL's own messages kept quiet (a target judges what Orbis returns, not what GDAL says).
// Include it in the target's one source file: it defines libFuzzer's initialisation hook.

#include <cpl_conv.h>
#include <cpl_error.h>
#include <gdal.h>

// GDAL 3.6.2's GML reader leaks an SRS on some srsName values (ogrinfo shows it under valgrind
// too): it is left out, or every run would stop on a leak that is not Orbis's. GDAL picks a
// driver by content, so a file's extension alone cannot keep GML out.
extern "C" int LLVMFuzzerInitialize(int*, char***) {
    CPLSetConfigOption("GDAL_SKIP", "GML NAS GMLAS");   // NAS reads GML with the same code
    GDALAllRegister();
    CPLSetErrorHandler(CPLQuietErrorHandler);
    return 0;
}
