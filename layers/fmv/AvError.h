#pragma once
// FFmpeg's error codes as text, and libsrt started once (private to the FMV video library).

extern "C" {
#include <libavutil/error.h>
}

#include <dlfcn.h>

#include <mutex>
#include <string>

namespace orbis::fmv {

inline std::string avError(int code) {
    char text[AV_ERROR_MAX_STRING_SIZE] = {};
    av_strerror(code, text, sizeof text);
    return text;
}

/// libsrt makes its global state in the first srt_startup(), which FFmpeg calls in every SRT
/// open: two threads opening their first SRT streams at once race in it (ThreadSanitizer sees
/// it). Called before any SRT open (the receiver's and the writer's), this starts it once, on
/// one thread, and keeps a reference that FFmpeg's opens and closes never drop. Nothing when
/// this FFmpeg has no libsrt.
inline void startSrtOnce() {
    static std::once_flag once;
    std::call_once(once, [] {
        if (void* f = dlsym(RTLD_DEFAULT, "srt_startup")) reinterpret_cast<int (*)()>(f)();
    });
}

}  // namespace orbis::fmv
