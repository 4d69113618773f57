#!/usr/bin/env python3
"""Large flat seeds for fuzz_scene, fuzz_sidecar and fuzz_gonio: inputs that are long rather
than deep (a flat array of 400 000 empty objects, an object of 80 000 keys, 25 000 goniometer
rows). A reader quadratic in their length spends minutes on each; the fuzzers' 10 s limit per
input then reports it. Each file stays under 2 MB; run-fuzzer.sh is given -max_len 2 MiB for
these targets so that they are not cut.

Usage: python3 fuzz/corpus/make_seeds_flat.py fuzz/corpus
"""
import os
import sys

out = sys.argv[1]
flat = "[" + ",".join(["{}"] * 400000) + "]"  # 1.2 MB
keys = "{" + ",".join('"k%d":{}' % i for i in range(80000)) + "}"  # 0.8 MB
scene_head = '{"tile": "100x100um", "materials": {"m": {"type": "mirror"}}, '


def write(rel, text):
    path = os.path.join(out, rel)
    with open(path, "w") as f:
        f.write(text)
    assert os.path.getsize(path) < 2 << 20, path


write("scene/flat_objects.json", scene_head + '"objects": ' + flat + "}")
write("scene/flat_note.json",
      scene_head + '"objects": [{"type": "plane", "material": "m"}], "note": ' + flat + "}")
write("scene/flat_materials.json",
      '{"tile": "100x100um", "materials": ' + keys.replace("{}", '{"type": "mirror"}', 1) +
      ', "objects": [{"type": "plane", "material": "k0"}]}')
write("sidecar/flat_array.json", '{"dx_m": 1e-6, "dy_m": 2e-6, "junk": ' + flat + "}")
write("sidecar/flat_keys.json", '{"dx_m": 1e-6, "junk": ' + keys + "}")
write("sidecar/flat_sources.json",
      '{"method": "naive", "sources": [' + ",".join(['"s.npy"'] * 200000) + "]}")
rows = ["theta_i_deg,phi_i_deg,theta_o_deg,phi_o_deg,wavelength_nm,brdf_per_sr"]
for i in range(25000):
    rows.append("%g,%g,%g,%g,550,%g" % (i % 80, (7 * i) % 360, (3 * i) % 85, (11 * i) % 360,
                                        0.5 + (i % 13) / 7))
write("gonio/many_rows.csv", "\n".join(rows) + "\n")
write("gonio/wide_header.csv",
      ",".join(["x%d" % i for i in range(100000)] +
               ["theta_i_deg,phi_i_deg,theta_o_deg,phi_o_deg,wavelength_nm,brdf_per_sr"]) +
      "\n" + ",".join(["0"] * 100000 + ["10,0,20,180,550,1"]) + "\n")
