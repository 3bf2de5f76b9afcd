set terminal pngcairo size 960,600 noenhanced font 'sans,10'
set output 'cradle_energy_vs_iterations.png'
set title 'Cradle: kinetic energy fraction reaching the last ball vs iterations'
set xlabel 'solver iterations'
set ylabel 'KE of last ball / initial KE'
set grid
set key outside right top
set logscale x
set format x '%g'
set yrange [0:1.05]
$d0 << EOD
1 1.20494409
2 0.354452613
4 0.466101251
8 0.446155815
10 0.444876861
20 0.444446013
50 0.444445568
EOD
$d1 << EOD
1 1.14062325
2 0.350223541
4 0.46621598
8 0.446155815
10 0.444876861
20 0.444446013
50 0.444445568
EOD
$d2 << EOD
1 0.493343946
2 0.491171153
4 0.473670693
8 0.465111341
10 0.464719624
20 0.464606704
50 0.464606639
EOD
$d3 << EOD
1 0.543887813
2 0.238123794
4 0.217906095
8 0.220812902
10 0.221321356
20 0.221679078
50 0.221684028
EOD
$d4 << EOD
1 0.5426279
2 0.235347687
4 0.217978125
8 0.220812902
10 0.221321356
20 0.221679078
50 0.221684028
EOD
$d5 << EOD
1 0.236921021
2 0.220723998
4 0.219436656
8 0.220982557
10 0.221158288
20 0.221261716
50 0.221262525
EOD
plot $d0 using 1:2 with linespoints title "Baumgarte float", \
     $d1 using 1:2 with linespoints title "SplitImpulse float", \
     $d2 using 1:2 with linespoints title "SoftStep float", \
     $d3 using 1:2 with linespoints dashtype 2 title "Baumgarte double", \
     $d4 using 1:2 with linespoints dashtype 2 title "SplitImpulse double", \
     $d5 using 1:2 with linespoints dashtype 2 title "SoftStep double"
