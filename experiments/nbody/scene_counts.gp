# Body pairs each test reports per frame, like the paper's Figs. 6-9 (the exact count in black).
# Usage: gnuplot -c scene_counts.gp FRAMES.csv OUT.svg|OUT.png   (FRAMES.csv as fcl_rs_scene --csv writes it)
# The variants (kdop18_realigned, rs_one_sided) are in the CSV only: the plot is busy enough.
if (ARGC < 2) { print "usage: gnuplot -c scene_counts.gp FRAMES.csv OUT.svg|OUT.png"; exit status 1 }
if (ARG2[strlen(ARG2)-3:] eq ".svg") {
  set terminal svg size 1200,500 dynamic font 'sans,12' background '#ffffff'
} else {
  set terminal pngcairo size 1500,625 font 'sans,12'
}
set output ARG2
set datafile separator ','
set key top left horizontal
# The title names the data file (fcl_rs_scene names it after the scene): its base name without ".csv".
name = ARG1
while (strstrt(name, "/") > 0) { name = name[strstrt(name, "/") + 1:] }
if (strlen(name) > 4 && name[strlen(name) - 3:] eq ".csv") { name = name[1:strlen(name) - 4] }
set title sprintf("Collisions reported per frame: %s", name) noenhanced
set xlabel 'frame'
set ylabel 'colliding pairs reported'
set grid
set yrange [0:*]
set offsets 0, 0, graph 0.12, 0
plot ARG1 using 'frame':'sphere' with lines lw 1 lc rgb '#1f77b4' title 'bounding sphere', \
     '' using 'frame':'aabb' with lines lw 1 lc rgb '#ff7f0e' title 'AABB', \
     '' using 'frame':'obb' with lines lw 1 lc rgb '#2ca02c' title 'OBB', \
     '' using 'frame':'kdop18' with lines lw 1 lc rgb '#9467bd' title 'KDOP18', \
     '' using 'frame':'rs' with lines lw 1.5 lc rgb '#d62728' title 'RS', \
     '' using 'frame':'exact' with lines lw 1.5 lc rgb '#000000' title 'exact (meshes intersect)'
