#!/usr/bin/env bash
# Many mechanisms at once against one long run: a 1000-case x 10 s sweep (1e7 physics steps)
# against one 10 000 s run (the same 1e7 steps), side by side in one go, each the best of three
# whole processes: the sweep one case at a time (--simd off), on the CPU's widest SIMD lanes with
# libm's sin/cos (the default: every lane the single run's bits) and with the vector sin/cos
# (--vector-trig); on one thread and on two.
# Usage: bash bench/batch_sweep.sh BUILD_DIR
# shellcheck source=common.sh
source "$(dirname "$0")/common.sh"
drive=(--torque-sine 2,0.5)
single=$(best_of_three "$simulate" --config "$config" --duration 10000 "${drive[@]}" \
  --output-rate 0.1 --csv "$work/single.csv")
width=$(/usr/bin/python3 -c "print({'avx512': 8, 'avx2': 4, 'sse2': 2}.get('$(grep -o -m1 -w avx512f /proc/cpuinfo >/dev/null && echo avx512 || (grep -q -m1 -w avx2 /proc/cpuinfo && echo avx2 || echo sse2))', 1))")
echo "one 10 000 s run (1e7 steps): $single s; SIMD width of this CPU: $width doubles"
echo "| 1000 cases x 10 s | threads | wall time [s] | / the single run |"
echo "|---|---|---|---|"
for jobs in 1 2; do
  for mode in "off" "auto" "auto --vector-trig"; do
    t=$(best_of_three "$simulate" --config "$config" --duration 10 "${drive[@]}" \
      --sweep mechanism.spring_stiffness=100:400:40 --sweep damping.slider4_joint=0:2:25 \
      --jobs "$jobs" --simd $mode --csv "$work/sweep.csv")
    printf "| --simd %s | %s | %.3f | %.2f |\n" "$mode" "$jobs" "$t" "$(echo "$t / $single" | bc -l)"
  done
done
# Short cases are mostly set-up (each case's config and its start-up check): 20 000 cases of one
# physics step and of 100, one thread, whole processes; a case's set-up is the one-step sweep's
# time per case (its one step, its CSV row and the process's start included: an upper bound).
grid=(--sweep mechanism.spring_stiffness=100:400:200 --sweep mechanism.rod_mass=0.5:2:100)
for duration in 0.001 0.1; do
  t=$(best_of_three "$simulate" --config "$config" --duration "$duration" "${drive[@]}" \
    "${grid[@]}" --jobs 1 --csv "$work/short.csv")
  printf "20 000 cases of %s s, one thread: %.3f s, %.1f us a case\n" "$duration" "$t" \
    "$(echo "$t * 1000000 / 20000" | bc -l)"
done
