#!/usr/bin/env node
// The worked problems' Möller–Trumbore ray/triangle test as a kernel of the line protocol
// (docs/kernel_protocol.md), written the naive textbook way in double (JavaScript numbers).
// rayproof catches it with false misses on rays that hit an edge or a vertex exactly.
//
// Run:
//   rayproof gen tri_edge -n 1000 > edge.txt
//   rayproof verify --methods double --exec 'mt-js=node examples/js/moller_trumbore.js' edge.txt
'use strict';
const readline = require('readline');

// Number() reads "Infinity" but not the protocol's words inf, -inf and nan.
function parse(word) {
  if (word === 'inf') return Infinity;
  if (word === '-inf') return -Infinity;
  if (word === 'nan') return NaN;
  return Number(word);
}

// String() writes Infinity and NaN, which the protocol spells inf and nan.
function format(x) {
  if (Number.isNaN(x)) return 'nan';
  if (x === Infinity) return 'inf';
  if (x === -Infinity) return '-inf';
  return String(x); // the shortest text that reads back to the same double
}

const sub = (a, b) => [a[0] - b[0], a[1] - b[1], a[2] - b[2]];
const cross = (a, b) => [a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0]];
const dot = (a, b) => a[0] * b[0] + a[1] * b[1] + a[2] * b[2];

// v: o(3) d(3) p0(3) p1(3) p2(3). Returns the answer line.
function triangle(v) {
  const o = v.slice(0, 3), d = v.slice(3, 6), p0 = v.slice(6, 9), p1 = v.slice(9, 12), p2 = v.slice(12, 15);
  const e1 = sub(p1, p0), e2 = sub(p2, p0), s = sub(o, p0);
  const s1 = cross(d, e2);
  const det = dot(s1, e1);
  if (det === 0) return 'miss'; // parallel to the plane, or in it: the naive test calls it a miss
  const s2 = cross(s, e1);
  const inv = 1 / det;
  const t = dot(s2, e2) * inv, b1 = dot(s1, s) * inv, b2 = dot(s2, d) * inv;
  if (!(b1 >= 0 && b2 >= 0 && 1 - b1 - b2 >= 0 && t >= 0)) return 'miss';
  return `hit ${format(t)} ${format(b1)} ${format(b2)}`;
}

process.stdout.write('rayproof-kernel 1 double triangle\n');
const answers = [];
const rl = readline.createInterface({ input: process.stdin, crlfDelay: Infinity });
rl.on('line', (line) => {
  const fields = line.trim().split(/\s+/);
  if (fields[0] === '') return;
  answers.push(triangle(fields.slice(1, 16).map(parse)));
  // Write in chunks: one write per line would be slow, and rayproof reads while it writes.
  if (answers.length >= 256) process.stdout.write(answers.splice(0).join('\n') + '\n');
});
rl.on('close', () => {
  if (answers.length) process.stdout.write(answers.join('\n') + '\n');
});
