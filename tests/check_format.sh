#!/bin/sh
# Fails when a C++ source differs from what clang-format (.clang-format) makes
# of it; lists the files. usage: check_format.sh SOURCE_DIR [CLANG_FORMAT]
root=${1:?usage: check_format.sh SOURCE_DIR [CLANG_FORMAT]}
cf=${2:-clang-format}
bad=0
for f in $(find "$root/include" "$root/src" "$root/tests" "$root/bench" -name '*.cpp' -o -name '*.hpp'); do
  if ! "$cf" --dry-run -Werror "$f" >/dev/null 2>&1; then
    echo "not formatted: $f (run: clang-format -i $f)"
    bad=1
  fi
done
[ $bad -eq 0 ] && echo "all C++ sources formatted"
exit $bad
