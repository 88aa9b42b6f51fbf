#pragma once
// FFmpeg's error codes as text (private to the FMV video library).

extern "C" {
#include <libavutil/error.h>
}

#include <string>

namespace orbis::fmv {

inline std::string avError(int code) {
    char text[AV_ERROR_MAX_STRING_SIZE] = {};
    av_strerror(code, text, sizeof text);
    return text;
}

}  // namespace orbis::fmv
