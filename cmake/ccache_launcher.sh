#!/bin/sh
# The compiler launcher when ccache and precompiled headers are both in use (see
# SystoleCompilerCache.cmake): `ccache_launcher.sh <ccache> <compiler> <arguments>`.
# ccache hashes every header a translation unit includes; the precompiled header is hundreds of
# MB, and hashing it took 3-4 s per translation unit even on a cache hit. With
# pch_external_checksum ccache hashes <header>.gch.sum instead, which this script writes (the
# SHA-256 of the .gch) whenever it builds or restores a precompiled header.
export CCACHE_SLOPPINESS=pch_defines,time_macros,include_file_mtime,include_file_ctime
export CCACHE_PCH_EXTSUM=true
ccache=$1
shift
out=
prev=
for arg in "$@"; do
  [ "$prev" = "-o" ] && out=$arg
  prev=$arg
done
case "$out" in
  *.gch) rm -f "$out.sum" ;;
  *) exec "$ccache" "$@" ;;
esac
"$ccache" "$@" || exit $?
sha256sum "$out" | cut -d' ' -f1 > "$out.sum"
