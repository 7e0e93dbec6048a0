# Draws fcl_rs_export's panels: gnuplot -c fcl_rs_export.gp MESH VOLUMES PANELS COLOURS OUT.png [OUT.svg]
#   MESH     the mesh's triangles (x y z, a blank line after each polygon)
#   VOLUMES  the volumes' triangles, one data block (index) per volume
#   PANELS   one line per panel: first volume block <tab> number of blocks <tab> caption
#   COLOURS  one line per volume block: its colour as rrggbb (hex; '#' starts a gnuplot comment)
# Every panel has the same ranges and view, so they share one camera; pm3d sorts all faces by depth.
mesh = ARG1; volumes = ARG2; panels = ARG3; colours = ARG4

set datafile separator "\t"
stats panels using 1 nooutput
n = STATS_records
palette_words = ""
stats colours using (palette_words = palette_words . " " . strcol(1), 0) nooutput
set datafile separator whitespace

# One cube around everything, so `view equal xyz` gives every panel the same scale.
stats mesh using 1:2 nooutput
xmin = STATS_min_x; xmax = STATS_max_x; ymin = STATS_min_y; ymax = STATS_max_y
stats volumes using 1:2 nooutput
xmin = (STATS_min_x < xmin) ? STATS_min_x : xmin; xmax = (STATS_max_x > xmax) ? STATS_max_x : xmax
ymin = (STATS_min_y < ymin) ? STATS_min_y : ymin; ymax = (STATS_max_y > ymax) ? STATS_max_y : ymax
stats mesh using 3 nooutput
zmin = STATS_min; zmax = STATS_max
stats volumes using 3 nooutput
zmin = (STATS_min < zmin) ? STATS_min : zmin; zmax = (STATS_max > zmax) ? STATS_max : zmax
half = 0.5 * ((xmax - xmin > ymax - ymin) ? ((xmax - xmin > zmax - zmin) ? xmax - xmin : zmax - zmin) \
                                        : ((ymax - ymin > zmax - zmin) ? ymax - ymin : zmax - zmin))
set xrange [(xmin + xmax) / 2 - half : (xmin + xmax) / 2 + half]
set yrange [(ymin + ymax) / 2 - half : (ymin + ymax) / 2 + half]
set zrange [(zmin + zmax) / 2 - half : (zmin + zmax) / 2 + half]

set view equal xyz
set view 65, 30, 1.7
unset border; unset tics; unset key; unset colorbox
set pm3d depthorder lighting primary 0.55 specular 0.15
set style fill transparent solid 0.28 noborder

do for [out_index = 5:6] {
  if (out_index == 5 || ARGC >= 6) {
    if (out_index == 5) {
      set terminal pngcairo size 420 * n, 480 font ",11"
      set output ARG5
    } else {
      set terminal svg size 420 * n, 480 font ",11"
      set output ARG6
    }
    set multiplot layout 1, n
    do for [i = 1:n] {
      set datafile separator "\t"
      stats panels every ::i-1::i-1 using (first = $1, count = $2, caption = strcol(3), 0) nooutput
      set datafile separator whitespace
      set title caption
      splot mesh with polygons fs solid 1.0 fc rgb "#b8b8b8", \
            for [j = first:first + count - 1] volumes index j with polygons fc rgb "#" . word(palette_words, j + 1)
    }
    unset multiplot
    set output
  }
}
