# One stability sweep. gnuplot -e "csv='...'; png='...'; ttl='...'; xl='...'; logx=1" stability.gp
set datafile separator ","
set terminal pngcairo size 1300,560 font "sans,10"
set output png
set logscale y
if (logx) set logscale x
set format y "%g"
set grid
set key outside right top box
labels = system(sprintf("awk -F, 'NR>1 && !s[$4]++ {print $4}' %s", csv))
sel(l) = sprintf("< awk -F, 'NR>1 && $4==\"%s\"' %s", l, csv)
fl(y) = y < 1e-9 ? 1e-9 : y
set multiplot layout 1,2 title ttl
set xlabel xl
set ylabel "RMS error per bin (dB; edge bins excluded)"
plot for [l in labels] sel(l) using 2:(fl($5)) with linespoints pt 7 title l
set ylabel "worst bin (dB; empty bins count 40 dB)"
plot for [l in labels] sel(l) using 2:(fl($6)) with linespoints pt 7 title l
unset multiplot
