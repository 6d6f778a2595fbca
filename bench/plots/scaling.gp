# Scaling charts. gnuplot -e "dir='results'" scaling.gp
set datafile separator ","
set terminal pngcairo size 1300,900 font "sans,10"
set output dir."/bench_scaling.png"
set grid
set key top right box
set multiplot layout 2,2 title "Scaling (standard workload settings: paper sonar, speckle, truth on)"
set logscale x 2
set xlabel "samples per channel"
set ylabel "pings/s"
thr(t) = sprintf("< awk -F, 'NR>1 && $2==%d' %s/scaling_samples.csv", t, dir)
plot for [t=1:2] thr(t) using 1:5 with linespoints pt 7 title sprintf("%d thread(s)", t)
unset logscale x
set logscale x 10
set xlabel "objects in the scene (0 plotted at 1)"
set logscale y 10
tho(t, p) = sprintf("< awk -F, 'NR>1 && $2==%d && $3==\"%s\"' %s/scaling_objects.csv", t, p, dir)
plot for [t=1:2] tho(t, "auto") using ($1 < 1 ? 1 : $1):6 with linespoints pt 7 title sprintf("default (auto planes), %d thread(s)", t), \
     for [t=1:2] tho(t, "1") using ($1 < 1 ? 1 : $1):6 with linespoints pt 6 dt 2 title sprintf("1 plane, %d thread(s)", t)
unset logscale y
set xlabel "grid cells"
set ylabel "pings/s (2 threads)"
set y2label "peak RSS (MiB)"
set y2tics
set logscale y2 10
plot dir."/scaling_grid.csv" using 1:5 every ::1 with linespoints pt 7 title "pings/s", \
     "" using 1:6 every ::1 axes x1y2 with linespoints pt 5 title "peak RSS (MiB)"
unset logscale x
unset logscale y2
set xlabel "survey length (km)"
set ylabel "pings/s (2 threads)"
set y2label "peak RSS (MiB)"
set yrange [0:*]
set y2range [0:*]
plot dir."/scaling_length.csv" using ($2/1000):4 every ::1 with linespoints pt 7 title "pings/s", \
     "" using ($2/1000):5 every ::1 axes x1y2 with linespoints pt 5 title "peak RSS (MiB)"
unset multiplot
