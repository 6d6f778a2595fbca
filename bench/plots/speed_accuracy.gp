# Speed vs accuracy chart of one scene. gnuplot -e "csv='...'; png='...'; ttl='...'" speed_accuracy.gp
set datafile separator ","
set terminal pngcairo size 1300,640 font "sans,10"
set output png
set logscale xy
set format y "%g"
set grid
set key outside bottom center horizontal maxrows 2 box
fam(f) = sprintf("< awk -F, 'NR>1 && $2==\"%s\"' %s", f, csv)
front = sprintf("< awk -F, 'NR>1 && $18==1' %s | sort -t, -k11 -g", csv)
dflt = sprintf("< awk -F, 'NR>1 && $19==1' %s", csv)
fl(y) = y < 1e-7 ? 1e-7 : y
families = "exact gauss subdiv planes objseg cell decimate rays"
set multiplot layout 1,2 title ttl
set xlabel "time per ping, both sides, 1 thread (ms)"
set ylabel "RMS error per bin, all lit bins (dB)"
plot for [f in families] fam(f) using 11:(fl($22)) with points pt 7 ps 1.2 title f, \
     front using 11:(fl($22)) with lines lw 2 lc rgb "black" dt 2 title "Pareto front", \
     dflt using 11:(fl($22)) with points pt 6 ps 3.5 lw 2 lc rgb "red" title "default"
set ylabel "worst bin (dB, empty bins count 40 dB)"
plot for [f in families] fam(f) using 11:(fl($13)) with points pt 7 ps 1.2 title f, \
     dflt using 11:(fl($13)) with points pt 6 ps 3.5 lw 2 lc rgb "red" title "default"
unset multiplot
