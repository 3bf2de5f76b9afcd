set terminal pngcairo size 960,600 noenhanced font 'sans,10'
set grid
set key top left
set xlabel 'time since start (s)'
set fit quiet logfile 'fit.log'
set object 1 rect from graph 0, graph 0 to first 360, graph 1 fc rgb '#eeeeee' behind
r(x) = ra + rb * x
f(x) = fa + fb * x
fit [360:*] r(x) 'soak.dat' u 1:($10 >= 0 ? $10 : 1/0) via ra, rb
fit [360:*] f(x) 'soak.dat' u 1:($11 >= 0 ? $11 : 1/0) via fa, fb
set output 'rss_fds.png'
set title 'server RSS and open file descriptors (grey: warm-up)'
set ylabel 'RSS (MiB)'
set y2label 'open fds'
set y2tics
plot 'soak.dat' u 1:($10 >= 0 ? $10 : 1/0) w l lw 2 t 'RSS MiB', '' u 1:($11 >= 0 ? $11 : 1/0) w l axes x1y2 t 'open fds', [360:*] r(x) w l dt 2 lc rgb 'black' t 'RSS fit', [360:*] f(x) axes x1y2 w l dt 3 lc rgb 'black' t 'fds fit'
unset y2tics
unset y2label
set output 'db.png'
set title 'database file and WAL'
set ylabel 'MiB'
plot 'soak.dat' u 1:($12 >= 0 ? $12 : 1/0) w l lw 2 t 'db + wal MiB'
set output 'tick_p99.png'
set title 'server tick time, worst match (last 600 ticks)'
set ylabel 'ms'
plot 'soak.dat' u 1:($2 > 0 ? $8 : 1/0) w l lw 2 t 'p99', '' u 1:($2 > 0 ? $9 : 1/0) w l t 'max', 4 w l lc rgb 'red' dt 3 t '4 ms'
set output 'snapshot_loss.png'
set title 'snapshot loss seen by bots (each scrape interval)'
set ylabel '%'
plot 'soak.dat' u 1:13 w l t 'loss %'
set output 'bots.png'
set title 'bots and what they did'
set ylabel 'bots'
set y2label 'since start'
set y2tics
plot 'soak.dat' u 1:3 w l lw 2 t 'playing', '' u 1:4 w l t 'joining', '' u 1:5 w l t 'gave up', '' u 1:16 w l axes x1y2 t 'sign-ins', '' u 1:18 w l axes x1y2 t 'left', '' u 1:19 w l axes x1y2 t 'matches finished', '' u 1:20 w l axes x1y2 t 'errors'
unset y2tics
unset y2label
set output 'cpu.png'
set title 'CPU (100 % = one core), from /proc'
set ylabel 'CPU %'
plot 'soak.dat' u 1:14 w l lw 2 t 'server', '' u 1:15 w l t 'generator'
set output 'errors.png'
set title 'errors by kind (whole run)'
set ylabel 'count'
unset object 1
set xlabel ''
set style fill solid 0.6
set boxwidth 0.6
set xtics rotate by -30
plot 'errors.dat' u 0:2:xtic(1) w boxes notitle
unset output
