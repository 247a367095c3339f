"""The seeds' shader listings: where each is printed, the text as printed, and the glue and edits that run it.

Every shader file in ``shaders/`` is the listing's lines copied verbatim from the seed text
(``../shared/seeds/*.txt``; the extraction's page-break fences and ``-----`` separator lines dropped,
nothing else; ``tests/local_models/test_listings.py`` checks each line against the seed). What the
harness (:mod:`validate.gl.listing_harness`) adds is listed per entry:

* ``header``: the ``#version`` line glued in front of a stage that prints none (then ``#line 1``);
* ``edits``: exact substitutions, each with its reason — extraction damage (a lost ``{``, an
  underscore read as a space, a LaTeX ``\\text{}``), a listing's line numbers and JavaScript string
  wrapper, or the book's own bug;
* ``glue_frag``: a whole stage the book does not print (Red Book Example 7.12 prints only a vertex shader).

``status``: ``printed`` (runs with glue only), ``edited`` (runs with the listed edits) or
``unrunnable`` (``reason`` says why; not run). ``runs`` is False for listings that compile but are
not exercised here (they need cube maps the suite does not build for them).

Seeds (file → book):
  000_9f0fc51ac170a018.txt  Fore June, *An Introduction to 3D Computer Graphics …*, ch. 20 "Shaders of Lighting"
  001_c43aa773178efb0f.txt  O. Stein, USC CSCI 420 lecture 11 "Lighting and Shading"
  002_97bcd7bbbb26ed7e.txt  R. Rost, *OpenGL Shading Language*, 2nd ed., §12.4 "The ÜberLight Shader"
  003_2c1b6bb878fe371f.txt  F. Ganovelli et al., *Introduction to Computer Graphics*, ch. 6 "Lighting and Shading"
  004_632c819d446da456.txt  D. Shreiner et al., *OpenGL Programming Guide* (Red Book), ch. 7 "Light and Shadow"
"""

from __future__ import annotations

from dataclasses import dataclass
from pathlib import Path

from ...errors import ValidateError
from ...gl.listing_harness import Edit, apply_edits, glued

SHADERS = Path(__file__).parent / "shaders"
SEED_FILES = {"forejune": "000_9f0fc51ac170a018.txt", "usc420": "001_c43aa773178efb0f.txt",
              "orange": "002_97bcd7bbbb26ed7e.txt", "ganovelli": "003_2c1b6bb878fe371f.txt",
              "redbook": "004_632c819d446da456.txt"}

GLSL110 = None  # no #version line: GLSL 1.10, the language these listings are written in
DOT_AS_SPACE = "the extraction printed the space after a type as '.' (`mat4.mvpMatrix`)"
GL_POSITION = "`gl_Position` extracted as `gl Position` (the underscore lost)"
OPEN_BRACE = "the `{` after `void main()` is lost in the extraction"
CLOSE_BRACE = "the closing `}` of main is lost in the extraction"
MAIN_VERT = (Edit("vert", "void main()\n", "void main()\n{\n", OPEN_BRACE),
             Edit("vert", "gl Position", "gl_Position", GL_POSITION))
FRAG_OPEN = Edit("frag", "void main()\n", "void main()\n{\n", OPEN_BRACE)
FRAG_CLOSE = Edit("frag", "FragColor = vec4(rgb, Color.a);\n", "FragColor = vec4(rgb, Color.a);\n}\n", CLOSE_BRACE)
PASS_THROUGH = "#version 330 core\nin vec3 Color;\nout vec4 FragColor;\nvoid main() { FragColor = vec4(Color, 1.0); }\n"


@dataclass(frozen=True)
class Listing:
    name: str
    seed: str  # key of SEED_FILES
    section: str
    number: str  # the book's listing / example number
    vert: str | None  # file in shaders/
    frag: str | None
    status: str  # printed | edited | unrunnable
    headers: tuple[str | None, str | None] = (None, None)  # (vertex, fragment) version glue
    edits: tuple[Edit, ...] = ()
    technique: str = ""  # what runs it (family/technique or module)
    reason: str = ""  # for unrunnable entries, or a note
    glue_frag: str | None = None  # a fragment stage the book does not print
    runs: bool = True
    computes: str = ""  # what the listing computes (index column)

    def text(self, stage: str) -> str:
        """The listing's stage exactly as printed (file contents)."""
        fname = self.vert if stage == "vert" else self.frag
        if fname is None:
            raise ValidateError(f"listing {self.name}: prints no {stage} shader")
        return (SHADERS / fname).read_text()

    def source(self, stage: str) -> str:
        """What is compiled: the printed text, its edits, its version glue."""
        if stage == "frag" and self.frag is None and self.glue_frag is not None:
            return self.glue_frag
        header = self.headers[0] if stage == "vert" else self.headers[1]
        return glued(apply_edits(self.text(stage), self.edits, stage, f"listing {self.name}"), header)


def _numbered(first: int, last: int, stage: str, skip: tuple[int, ...] = ()) -> tuple[Edit, ...]:
    """Strip Ganovelli's printed line numbers ``N `` at the start of lines first … last (except ``skip``)."""
    return tuple(Edit(stage, f"\n{k} ", "\n", "the listing prints line numbers", 0) for k in range(first, last + 1)
                 if k not in skip)


GANOVELLI_FRAG_WRAPPER = ("the listing is a JavaScript string (`shaderProgram.fragment_shader = “ … “ ;`) "
                          "with printed line numbers: both removed")

LISTINGS: tuple[Listing, ...] = (
    Listing("forejune_20_1", "forejune", "§20.2 Hemisphere Lighting", "Program Listing 20-1 (sphereh.vert/.frag)",
            "forejune_20_1_sphereh.vert", "forejune_20_1_sphereh.frag", "edited",
            edits=(Edit("vert", "mat4.mvpMatrix", "mat4 mvpMatrix", DOT_AS_SPACE),
                   Edit("vert", "vec4.vPosition", "vec4 vPosition", DOT_AS_SPACE),
                   Edit("vert", "vec3.N", "vec3 N", DOT_AS_SPACE),
                   Edit("vert", "int.objType", "int objType", DOT_AS_SPACE),
                   Edit("vert", "=.mvpMatrix", "= mvpMatrix", DOT_AS_SPACE),
                   Edit("frag", "vec3.N", "vec3 N", DOT_AS_SPACE),
                   Edit("frag", "vec4.skyColor", "vec4 skyColor", DOT_AS_SPACE),
                   Edit("frag", "vec4.groundColor", "vec4 groundColor", DOT_AS_SPACE),
                   Edit("frag", "vec3.skyDirection", "vec3 skyDirection", DOT_AS_SPACE)),
            technique="listings.diffuse_listings (GLSL vs Python transcription)",
            computes="hemisphere lighting C = mix(ground, sky, ½ + ½ n·u), eq. 20.7"),
    Listing("forejune_20_3", "forejune", "§20.3.2 Cubemaps", "sphereibl.vert/.frag (first version)",
            "forejune_20_3_sphereibl.vert", "forejune_20_3_sphereibl.frag", "edited",
            technique="not run", runs=False,
            reason="`.` for the space after each type in the declarations (as in Listing 20-1); needs a cube map of "
                   "the book's six photographs, and mix(light, env, 0.7) is a blend, not a radiometric quantity",
            computes="point light F = max(0, N·L) (eq. 20.8) mixed 30/70 with a mirror cube-map lookup (eq. 20.9)"),
    Listing("forejune_20_3b", "forejune", "§20.3.3 Cubemaps for Image-based Rendering", "sphereibl.vert/.frag "
            "(diffuse + specular maps)", "forejune_20_3b_sphereibl.vert", "forejune_20_3b_sphereibl.frag", "edited",
            technique="not run", runs=False,
            reason="a stray second `}` after main (delete it) and `.` for spaces in the declarations; needs the "
                   "diffuse and specular cube maps (HDRShop convolutions) the book does not give",
            computes="c_d·diffuseMap(N) mixed 50/50 with c_s·specularMap(r_v), eq. 20.10–20.11"),
    Listing("forejune_20_4_disc", "forejune", "§20.4.3 Analytical Light Source",
            "SH disc-source vertex/fragment shader", "forejune_20_4_sh_disc.vert", "forejune_20_4_sh_disc.frag",
            "printed", headers=("#version 120", "#version 120"),
            technique="listings.diffuse_listings (GLSL vs Python transcription)",
            reason="`radians ( 20 )` passes an int: GLSL 1.10 has no implicit int → float conversion, 1.20 does, "
                   "so the glue is `#version 120`",
            computes="E = 1.57079(1 − cos α) + 1.57080 sin²α z + 0.490874(cos α − cos³α)(3z² − 1), eq. 20.30, α = 20°"),
    Listing("forejune_20_4_grace", "forejune", "§20.4.4 Environment Map Light Source", "SH Grace Cathedral "
            "vertex/fragment shader", "forejune_20_4_sh_grace.vert", "forejune_20_4_sh_grace.frag", "printed",
            technique="listings.diffuse_listings (GLSL vs Python transcription)",
            computes="irradiance from 9 SH coefficients, eq. 20.33 (Table 20-1 Grace Cathedral)"),
    Listing("forejune_20_5", "forejune", "§20.5 Lighting of Cinematography", "uberlight-like vertex + fragment "
            "shader (Figure 20-17)", "forejune_20_5_uberlight.vert", "forejune_20_5_uberlight.frag", "printed",
            technique="listings.fore_june_uberlight (not a family technique: its normals assume a sphere at the "
                      "origin); experiment listings, uberlight_book: Figure 20-17's values vs the projector",
            computes="superellipse clip (eq. 20.41–20.42) × cuton/cutoff zones × the falloff (eq. 20.47 as coded: "
                     "pow(z/d0, beta)), diffuse max(N·L, 0) + (N·H)⁴ + ambient (0.5, 0.2, 0.2)"),
    Listing("usc420_l11", "usc420", "Phong Shader: Vertex/Fragment Program", "slides 'Phong Shader' (#version 150)",
            "usc420_l11_phong.vert", "usc420_l11_phong.frag", "printed", headers=(None, "#version 150"),
            technique="brdf/phong_usc420_glsl",
            reason="the fragment program prints no #version (the vertex program's `#version 150` is glued on; "
                   "`0.0f` and `in`/`out` need ≥ 1.30)",
            computes="c = k_a L_a + max(l·n, 0) k_d L_d + max(r·v, 0)^α k_s L_s, directional light in view space"),
    Listing("orange_12_6_12_7", "orange", "§12.4 The ÜberLight Shader", "Listings 12.6 (vertex) and 12.7 (fragment)",
            "orange_12_6_uberlight.vert", "orange_12_7_uberlight.frag", "printed",
            technique="uberlight/uberlight_orange_glsl; experiment listings: vs the projector",
            computes="superellipse barn shaping × distance shaping, 'plastic' ambient + diffuse + "
                     "(n·l)(n·h)·SurfaceRoughness specular (no exponent)"),
    Listing("ganovelli_6_3_6_4", "ganovelli", "§6.7.2 Upgrade Your Client: Add the Sun", "Listings 6.3 (vertex) and "
            "6.4 (fragment)", "ganovelli_6_3_lambert.vert", "ganovelli_6_4_lambert.frag", "edited",
            headers=("#version 100", "#version 100"),
            edits=(*_numbered(7, 32, "vert"),
                   Edit("vert", "6 precision", "precision", "the listing prints line numbers"),
                   Edit("vert", "\nmat3 uViewSpaceNormalMatrix;", "\nuniform mat3 uViewSpaceNormalMatrix;",
                        "the book's bug: the normal matrix is declared without `uniform` (a global never "
                        "assigned: the normals would be undefined) although Listing 6.2 uploads it as a uniform"),
                   Edit("vert", " position;          \n", " position;          \n}\n",
                        "the listing stops at line 32; main's closing `}` is not printed"),
                   Edit("frag", "36 shaderProgram.fragment_shader = “\n37 ", "", GANOVELLI_FRAG_WRAPPER),
                   *_numbered(38, 59, "frag"),
                   Edit("frag", "\n60} “ ;", "\n}", GANOVELLI_FRAG_WRAPPER)),
            technique="light/directional_ganovelli_glsl",
            reason="WebGL 1 GLSL ES 1.00 (`precision highp float;`): glue `#version 100`",
            computes="Lambert, directional light in view space: vdiffuse · uLightColor · max(0, N·L)"),
    Listing("ganovelli_6_9", "ganovelli", "§6.7.4 Upgrade Your Client: Add the Street Lamps", "Listing 6.9 "
            "(fragment; vertex: Listing 6.3)", "ganovelli_6_3_lambert.vert", "ganovelli_6_9_lamps.frag", "edited",
            headers=("#version 100", "#version 100"),
            edits=(*_numbered(7, 32, "vert"),
                   Edit("vert", "6 precision", "precision", "the listing prints line numbers"),
                   Edit("vert", "\nmat3 uViewSpaceNormalMatrix;", "\nuniform mat3 uViewSpaceNormalMatrix;",
                        "the book's bug in Listing 6.3 (see ganovelli_6_3_6_4)"),
                   Edit("vert", " position;          \n", " position;          \n}\n",
                        "Listing 6.3 stops before main's closing `}`"),
                   Edit("frag", "36 precision", "precision", "the listing prints line numbers"),
                   *_numbered(37, 68, "frag", skip=(63,)),
                   Edit("frag", "\n63}", "\n}", "the listing prints line numbers"),
                   Edit("frag", "\n69}\";", "\n}", GANOVELLI_FRAG_WRAPPER),
                   Edit("frag", "const int uNLights = “ + nLamps + “;", "const int uNLights = 1;",
                        "JavaScript splices the lamp count into the string; one lamp here"),
                   Edit("frag", "for (int i = 0; i <uNLights; {", "for (int i = 0; i <uNLights; ++i) {",
                        "the book's typo: the loop header lacks `++i)` (a syntax error as printed)")),
            technique="light/point_ganovelli_6_9_glsl",
            computes="Lambert from point lamps with r = 0.03·3.14·3.14·|p − x| and max(0, N·L)/r²"),
    Listing("ganovelli_6_12", "ganovelli", "§6.7.7 Add the Car's Headlights and Lights in the Tunnel",
            "Listing 6.12 (fragment-shader fragment)", None, "ganovelli_6_12_area.frag", "unrunnable",
            technique="not run",
            reason="a loop body only: no declarations of N, r, L, NdotL, lambert, vpos, uColor, uAreaLights*, no main, "
                   "and `for(int i = 0; i < uNAreaLights; ++i` lacks its `)`. Read: 3 × 2 point lights at "
                   "x ∈ {−s/2, +s/2}, y ∈ {−s/2, 0, +s/2} (the corners and edge midpoints, not cell centres), each "
                   "max(0, N·L)/(0.01·3.14²·r²)/6 — the inverse square scaled by 1/0.0986 = 10.1",
            computes="a rectangle light as 3 × 2 point lights"),
    Listing("ganovelli_6_13", "ganovelli", "§6.9.3 Upgrade Your Client: Use Phong Lighting", "Listing 6.13 "
            "(function phongShading)", None, "ganovelli_6_13_phong.frag", "unrunnable", technique="not run",
            reason="a function only (its varyings vambient, vdiffuse, vspecular, vshininess and its caller are not "
                   "printed); the function itself is the existing brdf/phong (ambient + max(0, N·L) + max(0, R·V)^n "
                   "with R = 2(N·L)N − L)",
            computes="Phong: ambient + diffuse max(0, N·L) + specular max(0, R·V)^n"),
    Listing("redbook_7_4", "redbook", "Point Lights", "Example 7.4", "redbook_7_4_point.vert", "redbook_7_4_point.frag",
            "edited",
            edits=(*MAIN_VERT, FRAG_OPEN, FRAG_CLOSE),
            technique="light/point_redbook_7_4_glsl",
            computes="(Ambient + LightColor·max(0, N·L)·att)·Color + LightColor·Strength·(N·H)^Shininess·att, "
                     "att = 1/(k_c + k_l d + k_q d²), saturated at 1"),
    Listing("redbook_7_5", "redbook", "Spotlights", "Example 7.5", "redbook_7_5_spot.vert", "redbook_7_5_spot.frag",
            "edited",
            edits=(*MAIN_VERT, FRAG_OPEN,
                   Edit("frag", "(spotCos < SpotCosCutoff)</pre>", "(spotCos < SpotCosCutoff)",
                        "an HTML `</pre>` tag left in the code by the extraction")),
            technique="light/spot_redbook_7_5_glsl",
            computes="Example 7.4 × (spotCos < SpotCosCutoff ? 0 : spotCos^SpotExponent)"),
    Listing("redbook_7_6", "redbook", "Moving Calculations to the Vertex Shader", "Example 7.6",
            "redbook_7_6_point_vertex.vert", "redbook_7_6_point_vertex.frag", "edited",
            edits=(*MAIN_VERT,
                   Edit("vert", "uniform float Linear Attenuation;", "uniform float LinearAttenuation;",
                        "a space inside the identifier `LinearAttenuation` (extraction)"),
                   FRAG_OPEN,
                   Edit("frag", "in vec3 HalfVector;", "in vec3 LightDirection;\nin vec3 HalfVector;",
                        "the book's bug: the fragment shader reads LightDirection but declares no `in` for it"),
                   FRAG_CLOSE),
            technique="light/point_redbook_7_6_glsl",
            reason="the vertex shader takes the light direction from the untransformed VertexPosition: lighting is "
                   "in model space (MV = identity here, so the same as Example 7.4)",
            computes="Example 7.4 with direction, half vector and attenuation per vertex"),
    Listing("redbook_7_8", "redbook", "Multiple Lights", "Example 7.8", None, None, "unrunnable", technique="not run",
            reason="the text lost the `} else {` between the local-light branch and `halfVector = "
                   "Lights[light].halfVector;` (as extracted the directional half vector overwrites the local one), "
                   "`continue:` for `continue;`, `ql Position`, and main's braces; per light it is Example 7.4/7.5",
            computes="loop over Example 7.4/7.5 lights with per-light ambient"),
    Listing("redbook_7_12", "redbook", "Hemisphere Lighting", "Example 7.12 (vertex shader)",
            "redbook_7_12_hemisphere.vert", None, "edited",
            edits=(Edit("vert", "uniform mat4 MVPMatrix;", "uniform mat4 MVMatrix;\nuniform mat4 MVPMatrix;",
                        "the book's bug: main reads MVMatrix, which the listing never declares"),),
            glue_frag=PASS_THROUGH,
            technique="listings.diffuse_listings (GLSL vs Python transcription)",
            reason="the book prints no fragment shader: a pass-through one is glued on",
            computes="a = ½ + ½ cos θ, Color = mix(Ground, Sky, a) (θ to the 'light position' north pole)"),
    Listing("redbook_7_14", "redbook", "Lighting with Spherical Harmonics", "Example 7.14", "redbook_7_14_sh.vert",
            "redbook_7_14_sh.frag", "edited",
            edits=(Edit("vert", "\\text{vec3}", "vec3", "LaTeX `\\text{vec3}` left by the extraction", 3),
                   Edit("vert", "gl Position", "gl_Position", GL_POSITION),
                   Edit("frag", "void main()\n", "void main()\n{\n", OPEN_BRACE),
                   Edit("frag", "FragColor = vec4 (DiffuseColor, 1.0);\n", "FragColor = vec4 (DiffuseColor, 1.0);\n}\n",
                        CLOSE_BRACE)),
            technique="listings.diffuse_listings (GLSL vs Python transcription)",
            computes="eq. 7.1 with the Old Town Square coefficients × ScaleFactor"),
    Listing("redbook_7_3", "redbook", "Directional Light", "Example 7.3", None, None, "unrunnable", technique="not run",
            reason="the fragment shader is cut after `specular = pow(specular, Shininess);` (the text after it is the "
                   "book's prose); Shininess and Strength are used but never declared in what is printed",
            computes="directional Blinn–Phong (the Example 7.4 terms without attenuation)"),
    Listing("redbook_7_20_7_21", "redbook", "Shadow Mapping", "Examples 7.15–7.21", None, None, "unrunnable",
            technique="not run (shadow family: no listing runs)",
            reason="Examples 7.15, 7.16, 7.17 and 7.19 are images ('Click here to view code image') with no text; "
                   "Example 7.21 stops at `float NdotL = dot(N, L);` and has spaces for underscores in its "
                   "identifiers (`depth texture`, `VS FS INTERFACE`). Only Example 7.18's host calls and the 7.20 "
                   "vertex shader are complete; the shadow test itself (textureProj on a sampler2DShadow) is in "
                   "the missing part",
            computes="depth-map shadows: textureProj(sampler2DShadow, shadow_coord) scales the light"),
)

BY_NAME = {x.name: x for x in LISTINGS}


def listing(name: str) -> Listing:
    try:
        return BY_NAME[name]
    except KeyError:
        raise ValidateError(f"unknown listing {name!r}; catalogued: {', '.join(BY_NAME)}") from None


__all__ = ["BY_NAME", "LISTINGS", "Listing", "SEED_FILES", "SHADERS", "listing"]
