#!/usr/bin/env bash
# Packs the built orbis and orbis-make-las with the Debian libraries they load (not glibc or
# libstdc++, which the target's newer ones replace) into one .tar.xz, to run benchmarks on a
# machine that has a GPU driver but not our packages (e.g. an Ubuntu 24.04 GPU box):
#   mkdir /tmp/orbis && tar -C /tmp/orbis -xJf orbis-bundle.tar.xz && . /tmp/orbis/env.sh
#   tools/bench-suite.sh /tmp/orbis
# STUB_FFMPEG=1 replaces FFmpeg (and the ~90 MB of codecs it pulls in) with stubs that abort
# when called: smaller, for scenes without video. The GL dispatch libraries that NVIDIA's Vulkan
# driver needs come along too.
#   usage: tools/portable-bundle.sh [BUILD_DIR] [OUT.tar.xz]
set -euo pipefail
here="$(cd "$(dirname "$0")/.." && pwd)"
build="${1:-$here/build}" out="$(realpath -m "${2:-orbis-bundle.tar.xz}")"
tmp="$(mktemp -d)"; trap 'rm -rf "$tmp"' EXIT
mkdir -p "$tmp/pkg/bin" "$tmp/pkg/lib" "$tmp/pkg/share/gdal"
cp "$build/bin/orbis" "$build/bin/orbis-make-las" "$tmp/pkg/bin/"
system='/(libc|libm|libdl|libpthread|librt|ld-linux-x86-64|libstdc\+\+|libgcc_s)\.so'
ffmpeg='/lib(avformat|avcodec|avutil|swscale|swresample)\.so'
closure() { ldd "$@" | awk '$3 ~ /^\// {print $3}' | sort -u | grep -Ev "$system"; }
if [ "${STUB_FFMPEG:-0}" = 1 ]; then
    direct=$(readelf -d "$build/bin/orbis" | sed -n 's/.*Shared library: \[\(.*\)\]/\1/p' | grep -Ev '^lib(av|sw)')
    libs=$( { for l in $direct; do p=$(ldconfig -p | awk -v l="$l" '$1 == l && /x86-64/ {print $NF; exit}');
              [ -n "$p" ] && { echo "$p"; closure "$p"; }; done; closure "$build/bin/orbis-make-las"; } |
            sort -u | grep -Ev "$system|$ffmpeg")
    syms=$(readelf --dyn-syms -W "$build/bin/orbis" | awk '$7 == "UND" {print $8}' | grep -E '@LIB(AV|SW)' || true)
    for ver in $(echo "$syms" | sed 's/.*@//' | sort -u); do
        so=$(readelf -d "$build/bin/orbis" | sed -n 's/.*Shared library: \[\(.*\)\]/\1/p' |
             grep -i "^lib$(echo "$ver" | sed 's/^LIB//; s/_[0-9]*$//' | tr 'A-Z' 'a-z')\.so")
        { echo '#include <stdio.h>'; echo '#include <stdlib.h>'
          for s in $(echo "$syms" | grep "@$ver\$" | cut -d@ -f1); do
              if [ "$s" = av_log_set_level ]; then echo "void $s(int l) { (void)l; }"
              else echo "void $s(void) { fputs(\"orbis bundle: FFmpeg was left out ($s)\\n\", stderr); abort(); }"; fi
          done; } > "$tmp/$so.c"
        printf '%s { global: *; };\n' "$ver" > "$tmp/$so.map"
        cc -shared -fPIC -o "$tmp/pkg/lib/$so" -Wl,-soname,"$so" -Wl,--version-script="$tmp/$so.map" "$tmp/$so.c"
    done
else
    libs=$(closure "$build/bin/orbis" "$build/bin/orbis-make-las")
fi
for l in $libs; do cp -L "$l" "$tmp/pkg/lib/"; done
for l in libGLdispatch.so.0 libGLX.so.0 libEGL.so.1 libX11.so.6 libX11-xcb.so.1 libxcb.so.1 libXau.so.6 \
         libXdmcp.so.6 libXext.so.6 libbsd.so.0 libmd.so.0; do
    [ -e "/lib/x86_64-linux-gnu/$l" ] && cp -nL "/lib/x86_64-linux-gnu/$l" "$tmp/pkg/lib/"
done
cp /usr/share/proj/proj.db "$tmp/pkg/share/"
cp -r /usr/share/gdal/. "$tmp/pkg/share/gdal/"
cat > "$tmp/pkg/env.sh" <<'ENV'
# source this: the bundle's libraries and data, and NVIDIA's Vulkan driver where it is installed
b="$(cd "$(dirname "${BASH_SOURCE[0]}")" && pwd)"
export LD_LIBRARY_PATH="$b/lib${LD_LIBRARY_PATH:+:$LD_LIBRARY_PATH}" PROJ_DATA="$b/share" GDAL_DATA="$b/share/gdal"
for f in /usr/local/nvidia/share/vulkan/icd.d/nvidia_icd.json /usr/share/vulkan/icd.d/nvidia_icd.json \
         /etc/vulkan/icd.d/nvidia_icd.json; do
    [ -z "${VK_ICD_FILENAMES:-}" ] && [ -f "$f" ] && export VK_ICD_FILENAMES="$f"
done
ENV
tar -C "$tmp/pkg" -cf - . | xz -9 -T0 > "$out"
echo "wrote $out ($(du -h "$out" | cut -f1))"
