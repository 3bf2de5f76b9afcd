set terminal pngcairo size 960,600 noenhanced font 'sans,10'
set output 'slope_roll_error_vs_cost.png'
set title 'slope_roll: position error after 2 s, m vs cost (dt 1/30 .. 1/1000)'
set xlabel 'ms of World::step per simulated second'
set ylabel 'position error after 2 s, m'
set grid
set key outside right top
set logscale x
set format x '%g'
set logscale y
set format y '%.0e'
$d0 << EOD
0.046355 0.0798864125
0.0859595 0.0399447649
0.185737 0.019971843
0.387234 0.00998147118
0.74182 0.00499575655
1.52537 0.00238858258
EOD
$d1 << EOD
0.041492 0.0798859626
0.081299 0.0399414227
0.182172 0.0199712712
0.352399 0.00998986186
0.69982 0.00499013401
1.50647 0.00240468073
EOD
$d2 << EOD
0.0459 2.2492203e-07
0.092418 3.04702285e-07
0.184058 3.87598541e-07
0.379739 1.03818649e-06
0.729806 2.99400724e-06
1.4928 1.52191836e-05
EOD
$d3 << EOD
0.043975 2.2492203e-07
0.081544 3.04702285e-07
0.178173 3.87598541e-07
0.365555 1.03818649e-06
0.757503 2.99400724e-06
1.54272 1.52191836e-05
EOD
$d4 << EOD
0.042251 0.0798861335
0.084279 0.0399430667
0.176041 0.0199715334
0.352207 0.00998576668
0.705038 0.00499288334
1.48266 0.002396584
EOD
$d5 << EOD
0.0437465 0.0798861335
0.080399 0.0399430667
0.162536 0.0199715334
0.341977 0.00998576668
0.684898 0.00499288334
1.41696 0.002396584
EOD
$d6 << EOD
0.040279 4.4408921e-15
0.0808385 1.77635684e-15
0.165885 8.8817842e-15
0.340898 1.0658141e-14
0.676566 7.10542736e-15
1.42157 3.28626015e-14
EOD
$d7 << EOD
0.0410955 4.4408921e-15
0.0969705 1.77635684e-15
0.196775 8.8817842e-15
0.415839 1.0658141e-14
0.832035 7.10542736e-15
1.73093 3.28626015e-14
EOD
plot $d0 using 1:2 with linespoints title "ExplicitEuler float", \
     $d1 using 1:2 with linespoints title "SemiImplicitEuler float", \
     $d2 using 1:2 with linespoints title "ExactBallistic float", \
     $d3 using 1:2 with linespoints title "Rk4 float", \
     $d4 using 1:2 with linespoints dashtype 2 title "ExplicitEuler double", \
     $d5 using 1:2 with linespoints dashtype 2 title "SemiImplicitEuler double", \
     $d6 using 1:2 with linespoints dashtype 2 title "ExactBallistic double", \
     $d7 using 1:2 with linespoints dashtype 2 title "Rk4 double"
