set terminal svg size 900,600 dynamic background rgb 'white' font 'Sans,12'
set output "error_vs_depth.svg"
set title 'Error against depth complexity (static scenes)'
set xlabel 'spheres along the pixel ray (list length)'
set ylabel 'mean |error| / peak'
set logscale y
set format y '%.0e'
set grid
set key outside right
plot 'error_vs_depth.dat' index 0 using 1:2 with linespoints title "auto", \
     'error_vs_depth.dat' index 1 using 1:2 with linespoints title "kbuf:16", \
     'error_vs_depth.dat' index 2 using 1:2 with linespoints title "kbuf:4", \
     'error_vs_depth.dat' index 3 using 1:2 with linespoints title "kbuf:8", \
     'error_vs_depth.dat' index 4 using 1:2 with linespoints title "peel:16", \
     'error_vs_depth.dat' index 5 using 1:2 with linespoints title "peel:4", \
     'error_vs_depth.dat' index 6 using 1:2 with linespoints title "peel:8", \
     'error_vs_depth.dat' index 7 using 1:2 with linespoints title "peel:dual:8", \
     'error_vs_depth.dat' index 8 using 1:2 with linespoints title "ppll", \
     'error_vs_depth.dat' index 9 using 1:2 with linespoints title "ppll-general", \
     'error_vs_depth.dat' index 10 using 1:2 with linespoints title "screendoor:2", \
     'error_vs_depth.dat' index 11 using 1:2 with linespoints title "screendoor:4", \
     'error_vs_depth.dat' index 12 using 1:2 with linespoints title "soft", \
     'error_vs_depth.dat' index 13 using 1:2 with linespoints title "sorted", \
     'error_vs_depth.dat' index 14 using 1:2 with linespoints title "stochastic:16", \
     'error_vs_depth.dat' index 15 using 1:2 with linespoints title "stochastic:4", \
     'error_vs_depth.dat' index 16 using 1:2 with linespoints title "stochastic:8", \
     'error_vs_depth.dat' index 17 using 1:2 with linespoints title "stochastic:8,depth", \
     'error_vs_depth.dat' index 18 using 1:2 with linespoints title "tiles", \
     'error_vs_depth.dat' index 19 using 1:2 with linespoints title "trace", \
     'error_vs_depth.dat' index 20 using 1:2 with linespoints title "wavg", \
     'error_vs_depth.dat' index 21 using 1:2 with linespoints title "wboit", \
     'error_vs_depth.dat' index 22 using 1:2 with linespoints title "wsum"
set terminal pngcairo size 900,600 font 'Sans,10'
set output "error_vs_depth.png"
replot
