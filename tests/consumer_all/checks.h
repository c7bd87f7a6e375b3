#pragma once
// One check per component; each prints what it checked and returns its number of failures.
int check_core();
int check_certified();
int check_verify();
int check_scene();
