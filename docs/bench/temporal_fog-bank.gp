set terminal svg size 900,600 dynamic background rgb 'white' font 'Sans,12'
set output "temporal_fog-bank.svg"
set title "Temporal error per frame step: fog-bank (spikes are pops)"
set xlabel 'frame step'
set ylabel 'mean |(I_t - I_{t-1}) - (R_t - R_{t-1})| / peak'
set logscale y
set format y '%.0e'
set grid
set key outside right
plot 'temporal_fog-bank.dat' index 0 using 1:2 with linespoints title "ppll", \
     'temporal_fog-bank.dat' index 1 using 1:2 with linespoints title "ppll-general", \
     'temporal_fog-bank.dat' index 2 using 1:2 with linespoints title "tiles", \
     'temporal_fog-bank.dat' index 3 using 1:2 with linespoints title "trace", \
     'temporal_fog-bank.dat' index 4 using 1:2 with linespoints title "auto", \
     'temporal_fog-bank.dat' index 5 using 1:2 with linespoints title "sorted", \
     'temporal_fog-bank.dat' index 6 using 1:2 with linespoints title "soft", \
     'temporal_fog-bank.dat' index 7 using 1:2 with linespoints title "wsum", \
     'temporal_fog-bank.dat' index 8 using 1:2 with linespoints title "wavg", \
     'temporal_fog-bank.dat' index 9 using 1:2 with linespoints title "wboit", \
     'temporal_fog-bank.dat' index 10 using 1:2 with linespoints title "kbuf:8", \
     'temporal_fog-bank.dat' index 11 using 1:2 with linespoints title "kbuf:4", \
     'temporal_fog-bank.dat' index 12 using 1:2 with linespoints title "kbuf:16", \
     'temporal_fog-bank.dat' index 13 using 1:2 with linespoints title "peel:8", \
     'temporal_fog-bank.dat' index 14 using 1:2 with linespoints title "peel:4", \
     'temporal_fog-bank.dat' index 15 using 1:2 with linespoints title "peel:16", \
     'temporal_fog-bank.dat' index 16 using 1:2 with linespoints title "peel:dual:8", \
     'temporal_fog-bank.dat' index 17 using 1:2 with linespoints title "stochastic:8", \
     'temporal_fog-bank.dat' index 18 using 1:2 with linespoints title "stochastic:4", \
     'temporal_fog-bank.dat' index 19 using 1:2 with linespoints title "stochastic:16", \
     'temporal_fog-bank.dat' index 20 using 1:2 with linespoints title "stochastic:8,depth", \
     'temporal_fog-bank.dat' index 21 using 1:2 with linespoints title "screendoor:4", \
     'temporal_fog-bank.dat' index 22 using 1:2 with linespoints title "screendoor:2"
set terminal pngcairo size 900,600 font 'Sans,10'
set output "temporal_fog-bank.png"
replot
