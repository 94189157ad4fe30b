#!/usr/bin/env bash
# The figure sheet (#37): for every thesis figure the project reproduces, our picture
# (input | result, from `asperity demo`) under out/figures/ beside the thesis' caption in
# out/figures/index.md. With --docs, writes docs/figures.md instead, pointing at the README
# gallery's copies (docs/gallery/, refreshed by scripts/gallery.sh).
set -euo pipefail
cd "$(dirname "$0")/.."

# figure | recipe | what the thesis says the figure shows (its caption or text, quoted) | our check
FIGURES=(
  "4.19|bunny-hair|\"simulating hair appearance\", made as Fig. 5.10 makes it: \"each point processed individually at a high resolution\" (a subdivided region, strands combed by phasor noise)|across the comb the displacement changes 2.2× as fast as along it; isotropic kernels 0.9× (the_hair_recipe_combs_strands_along_its_orientation)"
  "4.19–4.20|elephant-taper-twist|\"local tapering deformation\" (eq. 4.6–4.7) and \"global twisting operator\" (eq. 4.8–4.9)|taper and twist closed forms (tests: taper_and_twist_match_their_closed_forms)"
  "4.21|sphere-turbulence|\"Noise mapping and deformation over a sphere model\" (turbulence, gain 0.5, lacunarity 2.0)|amplitude is the peak displacement (amplitude_is_the_peak_displacement_of_every_kind)"
  "4.23|sphere-marble|\"This pattern resembles marble stripes\"|the displacement along x peaks at the sine's 8 cycles per diagonal (the_marble_recipe_makes_stripes_along_x_at_its_frequency)"
  "4.24|sphere-multifractal|multifractal noise over a sphere (eq. 4.12)|level modulation (level_modulation_attenuates_lacunarity_towards_coarser_levels)"
  "4.25|sphere-wood|wood rings, eq. 4.13|no edge jumps by more than 0.45 of the peak (wood_rings_never_jump_across_an_edge)"
  "4.28|fandisk-erosion|\"a erosion on the fandisk across feature lines\"|crease vertices worn 0.42 % of the diagonal on average (the_fandisk_erosion_recipe_wears_its_creases_visibly)"
  "5.1|torus-variation|multiscale variation: the fine turbulence only where nothing was noised before|fine roughness 0.119 on the turbulent half, 0.044 on the varied one (torus_variation_keeps_the_fine_turbulence_off_the_half_noised_at_a_coarse_level)"
  "5.2|femur-wearing|\"Wearing simulation, using Perlin noise to represent fraying or local damage\" (Gabor, Table 5.1)|Table 5.1 per-ring influence (propagation_follows_table_5_1_influence_per_ring)"
  "5.3a|femur-wearing-strong|\"Femur with a more intense erosion on the left side\" (\"the noise influence by a factor of two\")|deepest wear twice femur-wearing's in the focus, none far from it (the_stronger_femur_wearing_wears_one_side_of_the_head_twice_as_deep)"
  "5.5–5.6|sphere-virus|\"Virus looking surface with black coloring at the deformed areas\"|neighbouring faces at most 67.3° apart (the test allows 75°; the old recipe 153°), black at the most displaced vertex (the_virus_recipe_grows_smooth_extensions_coloured_where_deformed)"
  "5.7|mushroom-planet|\"a wide area at the top of the hill\": mushroom caps on stems|a cap's rim 1.14× its stem's distance from the axis (organic_widening_puts_a_cap_wider_than_its_stem)"
)

sheet() { # $1: picture folder as the sheet links it, $2: prefix of each picture's name
  echo "# The thesis' figures as asperity reproduces them"
  echo
  echo "Each row: the thesis figure, what the thesis says it shows, our input | result from"
  echo "\`recipes/NAME.toml\` (\`asperity demo\`; \`make figures\` writes them to \`out/figures/\`), and the"
  echo "measurable check a test makes of it."
  echo
  for row in "${FIGURES[@]}"; do
    IFS='|' read -r figure recipe caption check <<<"$row"
    echo "## Fig. $figure — \`recipes/$recipe.toml\`"
    echo
    echo "Thesis: $caption."
    echo
    echo "![Fig. $figure]($1/$2$recipe.png)"
    echo
    echo "Check: $check."
    echo
  done
}

if [[ "${1:-}" == "--docs" ]]; then
  sheet gallery detail- >docs/figures.md
  echo "figures: docs/figures.md (${#FIGURES[@]} figures)"
  exit 0
fi
cargo build --release -q --features cli
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
./target/release/asperity demo --out "$work" --quiet
mkdir -p out/figures
for row in "${FIGURES[@]}"; do
  IFS='|' read -r figure recipe _ <<<"$row"
  cp "$work/detail-$recipe.png" "out/figures/fig-${figure%%–*}-$recipe.png"
done
sheet . "" >out/figures/index.md
# The sheet names each picture by recipe; link them to the files written above.
for row in "${FIGURES[@]}"; do
  IFS='|' read -r figure recipe _ <<<"$row"
  sed -i "s|(./$recipe.png)|(./fig-${figure%%–*}-$recipe.png)|" out/figures/index.md
done
echo "figures: ${#FIGURES[@]} pictures and index.md under out/figures/"
