set terminal svg size 900,600 dynamic background rgb 'white' font 'Sans,12'
set output "speed_accuracy.svg"
set title 'Speed against accuracy (mean over scenes; lower left is better)'
set xlabel 'median frame time, ms (geometric mean over scenes)'
set ylabel 'RMSE / peak against the reference'
set logscale xy
set grid
set key outside bottom center horizontal
set format y '%.0e'
plot 'pareto_front.dat' using 1:2 with lines lw 2 lc rgb '#888888' title 'Pareto front', \
     'speed_accuracy.dat' using 2:3 with points pt 7 ps 1.5 title 'methods', \
     'speed_accuracy_labels.dat' using 1:2:3 with labels offset 1,0.7 left notitle
set terminal pngcairo size 900,600 font 'Sans,10'
set output "speed_accuracy.png"
replot
