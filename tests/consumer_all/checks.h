#pragma once
// One check per component; each prints what it checked and returns its number of failures.
int check_core();
int check_certified();  // also runs check_certified_sample()
int check_certified_sample();
int check_verify();
int check_scene();
