# The accuracy-time plot of fcl_rs_tradeoff: per BV type, one small point per mesh and a large one for the
# median over the meshes, as ratios to OBBRSS on the same mesh (left: BV tests against time; right: the
# false-positive share of BV tests against time).
# Usage: gnuplot -c tradeoff.gp POINTS.csv OUT.svg|OUT.png
#   POINTS.csv: what fcl_rs_tradeoff --plot OUT.svg writes beside the plot as OUT.points.csv (columns label,
#   series, kind (mesh or median), x, y, fp_percent, color, point, meshes).
if (ARGC < 2) { print "usage: gnuplot -c tradeoff.gp POINTS.csv OUT.svg|OUT.png"; exit status 1 }
set datafile separator ','
array names[1000]
array colors[1000]
array points[1000]
series = 0
meshes = 0
stats ARG1 using (s = int(column('series')) + 1, names[s] = strcol('label'), colors[s] = strcol('color'), \
                  points[s] = int(column('point')), series = (s > series ? s : series), \
                  meshes = int(column('meshes')), 0) nooutput
if (ARG2[strlen(ARG2) - 3:] eq ".svg") {
  set terminal svg size 1280,560 dynamic font 'sans,11'
} else {
  set terminal pngcairo size 1600,700 font 'sans,11'
}
set output ARG2
# Column `column` of the rows of series s of this kind, NaN (not drawn) elsewhere.
pick(s, kind, name) = (int(column('series')) == s - 1 && strcol('kind') eq kind) ? column(name) : NaN
set multiplot layout 1,2 title sprintf("fcl_rs_tradeoff: %d meshes, each against itself; small points = meshes, large = median; ratios to OBBRSS on the same mesh", meshes) noenhanced
set logscale xy
set grid
set xlabel 'us per exhaustive query / OBBRSS'
set ylabel 'BV tests per exhaustive query / OBBRSS'
unset key
plot for [s=1:series] ARG1 using (pick(s, 'mesh', 'x')):'y' with points pt points[s] ps 0.5 lc rgb colors[s] notitle, \
     for [s=1:series] ARG1 using (pick(s, 'median', 'x')):'y' with points pt points[s] ps 2 lw 2 lc rgb colors[s] notitle
unset logscale y
set ylabel 'false-positive share of BV tests (%)'
set key outside right top font ',9' spacing 0.9 noenhanced
plot for [s=1:series] ARG1 using (pick(s, 'mesh', 'x')):'fp_percent' with points pt points[s] ps 0.5 lc rgb colors[s] notitle, \
     for [s=1:series] ARG1 using (pick(s, 'median', 'x')):'fp_percent' with points pt points[s] ps 2 lw 2 lc rgb colors[s] title names[s]
unset multiplot
