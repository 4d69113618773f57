#!/usr/bin/env python3
"""Checks the shape of the code base that the compiler does not check.

  scripts/check-structure.py [ROOT]

1. Layers include only downwards:
     core <- surface <- ndf <- models <- brdf <- fit / simulate / render / texture / export
          <- report <- apps, python
   A file's layer is its folder under src/ (plot is a core utility), apps/ and python/ are the
   top; a public header's layer is given in PUBLIC_HEADERS below (a new header must be added
   there, so every header says where it belongs). Private headers of a src/ folder are included
   only from that folder, except src/core/ (helpers every layer may use).
2. Every apps/microbrdf/cmd_*.cpp is under 300 lines (parse the flags, call the library, print).
3. The material flag --metal is defined in one place of the CLI.

Prints every violation and exits 1 when there is one; tests/CMakeLists.txt runs it as a test.
"""
import pathlib
import re
import sys

LAYERS = {
    "core": 0, "plot": 0,
    "surface": 1,
    "ndf": 2,
    "models": 3,
    "brdf": 4,
    "fit": 5, "simulate": 5, "render": 5, "texture": 5, "export": 5, "measured": 5,
    "report": 6,
    "apps": 7, "python": 7,
}

# include/microbrdf/<name>.hpp -> the layer it belongs to.
PUBLIC_HEADERS = {
    # core: errors, units, files, images, numbers
    "error": "core", "units": "core", "atomic_file": "core", "run_inputs": "core", "image": "core", "vec3": "core",
    "quadrature": "core", "plot": "plot", "distribute": "core", "json_read": "core",
    "file_read": "core", "memory_budget": "core", "interrupt": "core", "threads": "core",
    "version": "core",
    "file_size_limit": "core", "duration": "core", "mpi_watchdog": "core",
    # surface: height maps, their files, statistics, levelling, generators, previews
    "surface": "surface", "io": "surface", "level": "surface", "generate": "surface",
    "statistics": "surface", "psd": "surface", "scanset": "surface", "ndf_scanset": "ndf", "height_preview": "surface",
    # ndf: tabulated distributions of normals and how they are estimated, stored and drawn
    "tabulated_ndf": "ndf", "ndf_estimate": "ndf", "ndf_io": "ndf", "ndf_preview": "ndf",
    "ndf_sampler": "ndf", "ndf_convolve": "ndf", "kirchhoff": "ndf", "filter_sigma_auto": "ndf",
    # models: distributions, Fresnel, spectra, Sun's and Westin's mathematics
    "microfacet": "models", "student_t": "models", "mixture_ndf": "models",
    "ndf_model": "models", "ndf_model_template": "models", "fresnel": "models", "spectrum": "models", "sun2002": "models",
    "sh_basis": "models", "tabulated_distribution": "models", "material_spec": "models",
    # brdf: the Brdf interface and every BRDF, the material and BRDF vocabulary
    "brdf": "brdf", "microfacet_brdf": "brdf", "brdf_albedo": "brdf", "brdf_slice": "brdf",
    "multiple_scattering": "brdf",
    "kirchhoff_brdf": "brdf", "sun_brdf": "brdf", "sh_brdf": "brdf", "lambertian_brdf": "brdf",
    "mirror_brdf": "brdf", "rayleigh_rice": "brdf", "regime": "brdf", "svbrdf": "brdf", "brdf_spec": "brdf", "measured": "brdf",
    "measured_ndf": "brdf", "rgl_bsdf": "brdf", "rgl_coords": "brdf", "tensor_file": "brdf",
    # experiments and products built on BRDFs
    "fit": "fit", "microscene": "simulate", "simulate": "simulate", "goniometer": "simulate",
    "render": "render", "envmap_image": "render", "sun_svbrdf": "render", "texture": "texture", "measured_compare": "fit", "export": "export",
    "scene_export": "export", "gltf_export": "export",
    "predict": "report",
}

INCLUDE = re.compile(r'^\s*#\s*include\s+"([^"]+)"', re.M)


def layer_of(path: pathlib.Path, root: pathlib.Path):
    rel = path.relative_to(root).parts
    if rel[0] == "src":
        return rel[1]
    if rel[0] == "include":
        return PUBLIC_HEADERS.get(path.stem)
    return rel[0]  # apps, python


def main() -> int:
    root = pathlib.Path(sys.argv[1] if len(sys.argv) > 1 else pathlib.Path(__file__).parent.parent)
    root = root.resolve()
    problems = []
    files = [p for d in ("src", "include", "apps", "python") for p in (root / d).rglob("*")
             if p.suffix in (".cpp", ".hpp", ".h", ".cc")]
    for header in (root / "include" / "microbrdf").glob("*.hpp"):
        if header.stem not in PUBLIC_HEADERS:
            problems.append(f"{header.relative_to(root)}: not in PUBLIC_HEADERS of "
                            "scripts/check-structure.py (say which layer it belongs to)")
    for f in sorted(files):
        own = layer_of(f, root)
        if own not in LAYERS:
            continue
        rel = f.relative_to(root)
        for inc in INCLUDE.findall(f.read_text(errors="replace")):
            parts = inc.split("/")
            if parts[0] == "microbrdf" and len(parts) == 2:
                stem = pathlib.Path(parts[1]).stem
                target = PUBLIC_HEADERS.get(stem)
                if target is None:
                    continue  # reported above (or not a header of this project)
            elif len(parts) == 2 and parts[0] in LAYERS:
                target = parts[0]
                if rel.parts[0] == "include":
                    problems.append(f"{rel}: public header includes the private header {inc}")
                    continue
                if target != "core" and target != own and rel.parts[0] == "src":
                    problems.append(f"{rel}: includes {inc}, a private header of src/{target}/ "
                                    "(move what it needs to a lower layer or a public header)")
                    continue
            else:
                continue  # same-folder or system include
            if LAYERS[target] > LAYERS[own]:
                problems.append(f"{rel} ({own}) includes {inc} ({target}): the include runs "
                                "up the layers")
    for cmd in sorted((root / "apps" / "microbrdf").glob("cmd_*.cpp")):
        lines = cmd.read_text().count("\n")
        if lines >= 300:
            problems.append(f"{cmd.relative_to(root)}: {lines} lines (commands stay under 300: "
                            "move the work into the library)")
    metal = [f"{p.relative_to(root)}" for p in sorted((root / "apps").rglob("*.cpp"))
             for _ in re.findall(r'add_option\(\s*"--metal[",]', p.read_text())]
    if len(metal) != 1:
        problems.append(f"--metal is defined {len(metal)} times in apps/ ({', '.join(metal)}): "
                        "define it once (add_material_flags)")
    for p in problems:
        print(p)
    print(f"check-structure: {len(files)} files, {len(problems)} problem(s)")
    return 1 if problems else 0


if __name__ == "__main__":
    sys.exit(main())
