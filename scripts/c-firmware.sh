#!/usr/bin/env bash
# The C example firmware (c-api/examples/firmware) on the mps2-an386 Cortex-M4F in QEMU:
# builds the thumbv7em-none-eabihf staticlib of maglev-c-api, compiles and links main.c with
# arm-none-eabi-gcc, runs it, and prints its report to stdout. Then checks it against the Rust
# `qemu-m4` image run the same way: the self-test trace lines (every configuration of the
# trace goes through the law type) must be identical, bit for bit, and one f32 paper-law
# update through the C API (`insns c-api f32/n1 update`) may take at most 1.10x the
# instructions of the Rust image's update through the same law type (`insns f32/n1 law-type
# update (maglev_core::Law)`), both counted the same way (QEMU -icount shift=10:
# instructions, not cycles); the Rust image's count of the paper controller alone
# (`Levitation::update`, no law dispatch) is printed beside them. Finally the linked image must hold
# no panic path. Needs gcc-arm-none-eabi, libnewlib-arm-none-eabi, qemu-system-arm and the
# thumbv7em-none-eabihf Rust target (docs/c-api.md). Exit 1 on any mismatch.
set -euo pipefail
cd "$(dirname "$0")/.."
out=target/c-firmware
mkdir -p "$out"
target=thumbv7em-none-eabihf
qemu=(qemu-system-arm -machine mps2-an386 -cpu cortex-m4 -nographic -monitor none
  -semihosting-config enable=on,target=native -icount shift=10 -kernel)

cargo build -q --release -p maglev-c-api --target "$target"
cargo build -q --release -p maglev-firmware-sim --target "$target" --bin qemu-m4
fw=c-api/examples/firmware
arm-none-eabi-gcc -mcpu=cortex-m4 -mthumb -mfloat-abi=hard -mfpu=fpv4-sp-d16 -O2 -g \
  -std=c11 -Wall -Wextra -Werror -ffunction-sections -fdata-sections \
  -nostdlib -T "$fw/link.ld" -Wl,--gc-sections -I c-api/include -I "$fw" \
  "$fw/main.c" "$fw/startup.c" "target/$target/release/libmaglev_c_api.a" -lgcc \
  -o "$out/c-firmware.elf"

timeout 120 "${qemu[@]}" "$out/c-firmware.elf" >"$out/c.txt" 2>"$out/c.err" ||
  { cat "$out/c.txt" "$out/c.err"; echo "c-firmware: the C image failed" >&2; exit 1; }
cat "$out/c.txt"
timeout 120 "${qemu[@]}" "target/$target/release/qemu-m4" >"$out/rust.txt" 2>"$out/rust.err" ||
  { cat "$out/rust.err"; echo "c-firmware: the Rust image failed" >&2; exit 1; }

trace='^(f32|i4f28)/(n1|n10p60v) [0-9][0-9] '
grep -E "$trace" "$out/c.txt" >"$out/c-trace.txt" || true
grep -E "$trace" "$out/rust.txt" >"$out/rust-trace.txt" || true
[ -s "$out/rust-trace.txt" ] || { echo "c-firmware: no trace lines from the Rust image" >&2; exit 1; }
diff -u "$out/rust-trace.txt" "$out/c-trace.txt" ||
  { echo "c-firmware: the C API's trace differs from the Rust image's" >&2; exit 1; }
echo "c-firmware: $(wc -l <"$out/c-trace.txt") trace lines identical to the Rust qemu-m4 image's"

# The nominal count (steps without events) of a count line: "<prefix>: nominal A..B, max C" -> B.
nominal() { sed -n "s|^$1: nominal [0-9]*\.\.\([0-9]*\),.*|\1|p" "$2"; }
c=$(nominal 'insns c-api f32/n1 update' "$out/c.txt")
law=$(nominal 'insns f32/n1 law-type update (maglev_core::Law)' "$out/rust.txt")
bare=$(nominal 'insns f32/n1 update' "$out/rust.txt")
[ -n "$c" ] && [ -n "$law" ] && [ -n "$bare" ] ||
  { echo "c-firmware: an instruction count is missing" >&2; exit 1; }
echo "c-firmware: one f32 paper-law update (n_sub = 1, steps without events), instructions:" \
  "C API $c, Rust through the law type $law (limit 1.10 x), Rust paper controller alone $bare"
if [ $((c * 100)) -gt $((law * 110)) ]; then
  echo "c-firmware: the C API's update takes more than 1.10 x the Rust law type's instructions" >&2
  exit 1
fi

if arm-none-eabi-nm -C "$out/c-firmware.elf" | grep -iE 'panic|rust_begin_unwind'; then
  echo "c-firmware: the linked C image holds a panic path (above)" >&2
  exit 1
fi
echo "c-firmware: no panic path in the linked image"
