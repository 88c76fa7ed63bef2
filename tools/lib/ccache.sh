# Sourced by tools/setup and tools/reliability: the compiler launcher that makes every build of this
# tree reuse ccache's objects, whichever folder the checkout is in (a fresh CI clone, a worktree).
#  - CCACHE_BASEDIR=<checkout>: paths under the checkout are hashed relative to it;
#  - CCACHE_NOHASHDIR: the build directory is not hashed (debug info keeps the first build's paths);
#  - the sloppiness lets it cache the tests, which use a precompiled header (docs/development.md).
# Usage: gpsemu_ccache_launcher ROOT  -> prints the -DCMAKE_CXX_COMPILER_LAUNCHER=... argument, or
# nothing when ccache is missing.
gpsemu_ccache_launcher() {
  local root=$1
  command -v ccache >/dev/null || return 0
  printf '%s' "-DCMAKE_CXX_COMPILER_LAUNCHER=env;CCACHE_BASEDIR=$root;CCACHE_NOHASHDIR=1;"
  printf '%s\n' "CCACHE_SLOPPINESS=pch_defines,time_macros,include_file_mtime,include_file_ctime,locale;ccache"
}
