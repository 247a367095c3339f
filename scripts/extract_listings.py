"""Provenance of validate/local_models/listings/shaders/ (run once): copy the listings' lines out of the seeds verbatim (fence lines ``` and ----- separators dropped)."""
from pathlib import Path
ROOT = Path(__file__).resolve().parent.parent
SEEDS = ROOT.parent / "shared" / "seeds"  # the shared/ folder beside the checkout
OUT = ROOT / "validate" / "local_models" / "listings" / "shaders"
F = {"forejune": "000_9f0fc51ac170a018.txt", "usc420": "001_c43aa773178efb0f.txt", "orange": "002_97bcd7bbbb26ed7e.txt",
     "ganovelli": "003_2c1b6bb878fe371f.txt", "redbook": "004_632c819d446da456.txt"}
R = {
 "forejune_20_1_sphereh.vert": ("forejune", [(77, 93)]),
 "forejune_20_1_sphereh.frag": ("forejune", [(99, 105), (109, 116)]),
 "forejune_20_3_sphereibl.vert": ("forejune", [(263, 289)]),
 "forejune_20_3_sphereibl.frag": ("forejune", [(293, 299), (303, 308), (320, 330)]),
 "forejune_20_3b_sphereibl.vert": ("forejune", [(373, 380), (384, 398)]),
 "forejune_20_3b_sphereibl.frag": ("forejune", [(400, 418)]),
 "forejune_20_4_sh_disc.vert": ("forejune", [(557, 557), (561, 584)]),
 "forejune_20_4_sh_disc.frag": ("forejune", [(588, 588), (592, 592), (596, 601)]),
 "forejune_20_4_sh_grace.vert": ("forejune", [(651, 667), (671, 694)]),
 "forejune_20_4_sh_grace.frag": ("forejune", [(696, 704)]),
 "forejune_20_5_uberlight.vert": ("forejune", [(848, 877)]),
 "forejune_20_5_uberlight.frag": ("forejune", [(904, 908), (912, 968), (972, 991)]),
 "usc420_l11_phong.vert": ("usc420", [(683, 683), (687, 688), (695, 696), (703, 705), (720, 730)]),
 "usc420_l11_phong.frag": ("usc420", [(736, 738), (749, 752), (759, 762), (773, 784)]),
 "orange_12_6_uberlight.vert": ("orange", [(59, 83)]),
 "orange_12_7_uberlight.frag": ("orange", [(93, 190)]),
 "ganovelli_6_3_lambert.vert": ("ganovelli", [(406, 432)]),
 "ganovelli_6_4_lambert.frag": ("ganovelli", [(438, 462)]),
 "ganovelli_6_9_lamps.frag": ("ganovelli", [(587, 620)]),
 "ganovelli_6_12_area.frag": ("ganovelli", [(714, 732)]),
 "ganovelli_6_13_phong.frag": ("ganovelli", [(854, 872)]),
 "redbook_7_4_point.vert": ("redbook", [(174, 191)]),
 "redbook_7_4_point.frag": ("redbook", [(193, 210), (214, 236)]),
 "redbook_7_5_spot.vert": ("redbook", [(257, 273)]),
 "redbook_7_5_spot.frag": ("redbook", [(275, 285), (289, 326)]),
 "redbook_7_6_point_vertex.vert": ("redbook", [(343, 368), (372, 378)]),
 "redbook_7_6_point_vertex.frag": ("redbook", [(380, 407)]),
 "redbook_7_12_hemisphere.vert": ("redbook", [(726, 728), (731, 747)]),
 "redbook_7_14_sh.vert": ("redbook", [(883, 909), (913, 925)]),
 "redbook_7_14_sh.frag": ("redbook", [(927, 932)]),
}
for name, (seed, ranges) in R.items():
    lines = (SEEDS / F[seed]).read_text().splitlines()
    out = []
    for a, b in ranges:
        for ln in lines[a - 1:b]:
            if ln.strip() in ("```",) or set(ln.strip()) <= set("-") and ln.strip():
                continue
            out.append(ln)
    (OUT / name).write_text("\n".join(out).rstrip("\n") + "\n")
    print(name, len(out))
