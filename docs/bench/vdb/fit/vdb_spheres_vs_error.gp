set terminal svg size 900,600 dynamic background rgb 'white' font 'Sans,12'
set output "vdb_spheres_vs_error.svg"
set title 'OpenVDB import: spheres against measured optical-depth error'
set xlabel 'spheres'
set ylabel 'RMS optical-depth error (relative)'
set logscale xy
set format x '10^{%L}'
set format y '%.0e'
set grid
set key top right
plot 'vdb_spheres_vs_error.dat' index 0 using 1:2 with linespoints title "cloud 128^3", \
     'vdb_spheres_vs_error.dat' index 1 using 1:2 with linespoints title "cloud 128^3 fit", \
     'vdb_spheres_vs_error.dat' index 2 using 1:2 with linespoints title "fog-sphere 128^3", \
     'vdb_spheres_vs_error.dat' index 3 using 1:2 with linespoints title "fog-sphere 128^3 fit", \
     'vdb_spheres_vs_error.dat' index 4 using 1:2 with linespoints title "sheet 128^3", \
     'vdb_spheres_vs_error.dat' index 5 using 1:2 with linespoints title "sheet 128^3 fit"
set terminal pngcairo size 900,600 font 'Sans,10'
set output "vdb_spheres_vs_error.png"
replot
