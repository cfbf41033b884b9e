set terminal svg size 720,440
set output 'scale.svg'
set logscale xy
set key left top
set xlabel 'fragments (list nodes) per frame'
set ylabel 'ms per frame'
set title 'brume bench scale: 640x360 smoke clouds, NVIDIA H200'
plot 'scale.dat' index 0 using 2:3 with linespoints title 'ppll', 'scale.dat' index 1 using 2:3 with linespoints title 'ppll-general', 'scale.dat' index 2 using 2:3 with linespoints title 'tiles', 'scale.dat' index 3 using 2:3 with linespoints title 'trace', 'scale.dat' index 4 using 2:3 with linespoints title 'reference', 'scale.dat' index 5 using 2:3 with linespoints title 'auto', 'scale.dat' index 6 using 2:3 with linespoints title 'sorted'
set terminal pngcairo size 720,440
set output 'scale.png'
replot
