#!/bin/bash
# prints: index shoulders-hc crossings-hc shift for first 46 debug lines with labels
labels=(paper tank+4 tank+10 tank+16 tank+30 tank-8 rad1 rad2 rad3 rad4 s01+2:-2 s01+26:0 s02+6:0 s02-10:-2 s04+26:0 s04-10:-2 s06+18:-2 s06+22:0 s07+14:-2 s07-2:0 s08+2:-2 s08+14:0)
cd "$(dirname "$0")/../../.."
build/uwbaccuracy --targets ${UWB_DATA:-/work/shared/data} tests/fixtures 2>&1 >/tmp/s3out.txt | grep HCDBG > /tmp/s3d.txt
i=0
while read -r l; do
  lab=${labels[$i]:-x$i}
  echo "$lab $l" | awk '{printf "%-12s cross %7s sh %7s shift %7s\n",$1,$4,$6,$12}'
  i=$((i+1))
done < /tmp/s3d.txt
