#!/usr/bin/env bash
# test_config_files.sh - what a config file may be (issue 22, items 7 and 19):
# only a regular file of bounded size and nesting, as the main config, an
# @include or a candidate's config; anything else is refused at once (exit 2)
# with the file named, never waited on or read without end.
# Usage: test_config_files.sh PATH/TO/pomlab SOURCE_DIR
set -u
POMLAB=$1
SRC=$2
. "$(dirname "$0")/cli_lib.sh"

CFG="$SRC/configs/3pss.cfg"
# expect_rc allows 120 s; a hang here must fail in seconds
quick() { expect_rc "$1" timeout 10 "${@:2}"; }

# --- item 7: a FIFO or a device as the config, an @include or a candidate -------
mkfifo "$TMP/fifo.cfg"
quick 2 "$POMLAB" model "$TMP/fifo.cfg"
expect_err "$TMP/fifo.cfg: is a FIFO (named pipe), not a config file"
quick 2 "$POMLAB" model /dev/zero
expect_err "/dev/zero: is a character device, not a config file"
quick 2 "$POMLAB" simulate /dev/null --target 1,1,1
expect_err "/dev/null: is a character device"
cp "$CFG" "$TMP/inc.cfg"
echo '@include "/dev/urandom"' >>"$TMP/inc.cfg"
quick 2 "$POMLAB" model "$TMP/inc.cfg"
expect_err "@include \"/dev/urandom\": /dev/urandom: is a character device"
cp "$CFG" "$TMP/incf.cfg"
echo '@include "fifo.cfg"' >>"$TMP/incf.cfg"
quick 2 "$POMLAB" model "$TMP/incf.cfg"
expect_err "@include \"fifo.cfg\": $TMP/fifo.cfg: is a FIFO"
printf 'name = "s"; montecarlo = { maneuvers = 2; seed = 1; };\n%s\n' \
  'candidates = ( { name = "A"; config = "fifo.cfg"; } );' >"$TMP/study.cfg"
quick 2 "$POMLAB" study "$TMP/study.cfg" --out "$TMP/s.h5" --quiet --no-plots --no-summary
expect_err "candidate 'A': $TMP/fifo.cfg: is a FIFO"
check "no results file for a refused study" [ ! -e "$TMP/s.h5" ]
# a candidate config that includes a device
cp "$CFG" "$TMP/cinc.cfg"
echo '@include "/dev/zero"' >>"$TMP/cinc.cfg"
printf 'name = "s"; montecarlo = { maneuvers = 2; seed = 1; };\n%s\n' \
  "candidates = ( { name = \"A\"; config = \"$TMP/cinc.cfg\"; } );" >"$TMP/study2.cfg"
quick 2 "$POMLAB" study "$TMP/study2.cfg" --out "$TMP/s.h5" --quiet --no-plots --no-summary
expect_err "/dev/zero: is a character device"

# --- item 7: a config's size is bounded, with the bound in the message ----------
head -c 17000000 /dev/zero | tr '\0' ' ' >"$TMP/big.cfg"
quick 2 "$POMLAB" model "$TMP/big.cfg"
expect_err "$TMP/big.cfg: 17000000 bytes, larger than a config file may be (at most 16777216 bytes"
cp "$CFG" "$TMP/incbig.cfg"
echo '@include "big.cfg"' >>"$TMP/incbig.cfg"
quick 2 "$POMLAB" model "$TMP/incbig.cfg"
expect_err "@include \"big.cfg\": $TMP/big.cfg: 17000000 bytes"
# a config below the bound still loads (comments pad it to 1 MB)
cp "$CFG" "$TMP/padded.cfg"
"$PY" -c "print(('#' * 99 + chr(10)) * 10000, end='')" >>"$TMP/padded.cfg"
quick 0 "$POMLAB" model "$TMP/padded.cfg" --json

# --- item 19: nesting deeper than libconfig's parser copes with -----------------
"$PY" -c "print('a = ' + '{ b = ' * 9000 + '1;' + ' };' * 9000)" >"$TMP/deep.cfg"
quick 2 "$POMLAB" model "$TMP/deep.cfg"
expect_err "$TMP/deep.cfg:1: groups, lists and arrays nested deeper than 64 levels"
check "no libconfig 'memory exhausted'" bash -c "! grep -q 'memory exhausted' '$TMP/err'"
"$PY" -c "print('x = ' + '(' * 70 + '1' + ')' * 70 + ';')" >"$TMP/deeplist.cfg"
cp "$CFG" "$TMP/incdeep.cfg"
echo '@include "deeplist.cfg"' >>"$TMP/incdeep.cfg"
quick 2 "$POMLAB" model "$TMP/incdeep.cfg"
expect_err "deeplist.cfg:1: groups, lists and arrays nested deeper than 64 levels"
# brackets in strings and comments are not nesting
cp "$CFG" "$TMP/brackets.cfg"
"$PY" -c "print('# ' + '{' * 100); print('/* ' + '(' * 100 + ' */')" >>"$TMP/brackets.cfg"
quick 0 "$POMLAB" model "$TMP/brackets.cfg" --json

finish test_config_files
