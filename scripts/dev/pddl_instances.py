#!/usr/bin/env python3
"""Generates the PDDL test and benchmark instances in test/data/pddl/ for the domains
there (gripper, blocksworld, logistics, depot, miconic): the instance families of the
IPC with their usual parameters, random ones from fixed seeds. Development aid; the
build does not run it. Usage: scripts/dev/pddl_instances.py test/data/pddl"""
import os
import random
import sys

OUT = sys.argv[1] if len(sys.argv) > 1 else "test/data/pddl"


def write(path, text):
    with open(os.path.join(OUT, path), "w") as f:
        f.write(text)


def gripper(n, typed):
    balls = [f"ball{i}" for i in range(1, n + 1)]
    if typed:
        objects = f"rooma roomb - room {' '.join(balls)} - ball left right - gripper"
        facts = ["(at-robby rooma)", "(free left)", "(free right)"]
        domain = "gripper-typed"
    else:
        objects = "rooma roomb " + " ".join(balls) + " left right"
        facts = ["(room rooma)", "(room roomb)", "(gripper left)", "(gripper right)", "(at-robby rooma)",
                 "(free left)", "(free right)"] + [f"(ball {b})" for b in balls]
        domain = "gripper-strips"
    facts += [f"(at {b} rooma)" for b in balls]
    goal = " ".join(f"(at {b} roomb)" for b in balls)
    return (f"(define (problem gripper-{n})\n  (:domain {domain})\n  (:objects {objects})\n"
            f"  (:init {' '.join(facts)})\n  (:goal (and {goal})))\n")


def towers(blocks, rng):
    stacks = []
    for b in blocks:
        r = rng.randrange(len(stacks) + 1)
        if r == len(stacks):
            stacks.append([b])
        else:
            stacks[r].append(b)
    return stacks


def blocks_problem(n, seed):
    rng = random.Random(seed)
    blocks = [f"b{i}" for i in range(1, n + 1)]
    order = blocks[:]
    rng.shuffle(order)
    init_towers = towers(order, rng)
    order = blocks[:]
    rng.shuffle(order)
    goal_towers = towers(order, rng)
    init = ["(handempty)"]
    for t in init_towers:
        init.append(f"(ontable {t[0]})")
        init += [f"(on {t[i]} {t[i - 1]})" for i in range(1, len(t))]
        init.append(f"(clear {t[-1]})")
    goal = []
    for t in goal_towers:
        goal += [f"(on {t[i]} {t[i - 1]})" for i in range(1, len(t))]
    if not goal:
        goal = [f"(ontable {b})" for b in blocks]
    return (f"(define (problem blocks-{n}-{seed})\n  (:domain blocks)\n  (:objects {' '.join(blocks)})\n"
            f"  (:init {' '.join(init)})\n  (:goal (and {' '.join(goal)})))\n")


def logistics(cities, packages, airplanes, seed):
    rng = random.Random(seed)
    objs, init = [], []
    city = [f"c{i}" for i in range(cities)]
    airport = [f"apt{i}" for i in range(cities)]
    loc = [f"pos{i}" for i in range(cities)]
    trucks = [f"tru{i}" for i in range(cities)]
    planes = [f"apn{i}" for i in range(airplanes)]
    pkgs = [f"obj{i}" for i in range(packages)]
    objs = (f"{' '.join(city)} - city {' '.join(airport)} - airport {' '.join(loc)} - location "
            f"{' '.join(trucks)} - truck {' '.join(planes)} - airplane {' '.join(pkgs)} - package")
    for i in range(cities):
        init += [f"(in-city {airport[i]} {city[i]})", f"(in-city {loc[i]} {city[i]})", f"(at {trucks[i]} {loc[i]})"]
    for p in planes:
        init.append(f"(at {p} {rng.choice(airport)})")
    places = airport + loc
    goal = []
    for p in pkgs:
        start = rng.choice(places)
        init.append(f"(at {p} {start})")
        goal.append(f"(at {p} {rng.choice([x for x in places if x != start])})")
    return (f"(define (problem logistics-{cities}-{packages}-{seed})\n  (:domain logistics)\n  (:objects {objs})\n"
            f"  (:init {' '.join(init)})\n  (:goal (and {' '.join(goal)})))\n")


def depot(crates, seed):
    rng = random.Random(seed)
    places = ["depot0", "distributor0", "distributor1"]
    pallets = ["pallet0", "pallet1", "pallet2"]
    hoists = ["hoist0", "hoist1", "hoist2"]
    trucks = ["truck0", "truck1"]
    cs = [f"crate{i}" for i in range(crates)]
    objs = (f"depot0 - depot distributor0 distributor1 - distributor {' '.join(trucks)} - truck "
            f"{' '.join(pallets)} - pallet {' '.join(cs)} - crate {' '.join(hoists)} - hoist")
    init = []
    tops = {}
    for i, p in enumerate(pallets):
        init += [f"(at {p} {places[i]})", f"(at {hoists[i]} {places[i]})", f"(available {hoists[i]})"]
        tops[p] = p
    for t in trucks:
        init.append(f"(at {t} {rng.choice(places)})")
    for c in cs:
        p = rng.choice(pallets)
        init += [f"(at {c} {places[pallets.index(p)]})", f"(on {c} {tops[p]})"]
        tops[p] = c
    for p in pallets:
        init.append(f"(clear {tops[p]})")
    goal_tops = {p: p for p in pallets}
    goal = []
    order = cs[:]
    rng.shuffle(order)
    for c in order[: max(1, crates - 1)]:
        p = rng.choice(pallets)
        goal.append(f"(on {c} {goal_tops[p]})")
        goal_tops[p] = c
    return (f"(define (problem depot-{crates}-{seed})\n  (:domain depot)\n  (:objects {objs})\n"
            f"  (:init {' '.join(init)})\n  (:goal (and {' '.join(goal)})))\n")


def miconic(floors, passengers, seed):
    rng = random.Random(seed)
    fs = [f"f{i}" for i in range(floors)]
    ps = [f"p{i}" for i in range(passengers)]
    init = [f"(floor {f})" for f in fs] + [f"(passenger {p})" for p in ps]
    init += [f"(above {fs[i]} {fs[j]})" for i in range(floors) for j in range(i + 1, floors)]
    for p in ps:
        a, b = rng.sample(fs, 2)
        init += [f"(origin {p} {a})", f"(destin {p} {b})"]
    init.append("(lift-at f0)")
    goal = " ".join(f"(served {p})" for p in ps)
    return (f"(define (problem miconic-{floors}-{passengers}-{seed})\n  (:domain miconic)\n"
            f"  (:objects {' '.join(fs + ps)})\n  (:init {' '.join(init)})\n  (:goal (and {goal})))\n")


for n in (4, 6, 8, 10):
    write(f"gripper/p{n}.pddl", gripper(n, False))
for n in (4, 6):
    write(f"gripper/typed-p{n}.pddl", gripper(n, True))
for n, seed in ((4, 1), (5, 2), (6, 3), (7, 4), (9, 5), (14, 6)):
    write(f"blocks/p{n}-{seed}.pddl", blocks_problem(n, seed))
for c, p, a, seed in ((2, 2, 1, 1), (2, 3, 1, 2), (3, 4, 1, 3), (4, 8, 2, 4), (5, 12, 2, 5)):
    write(f"logistics/p{c}-{p}-{seed}.pddl", logistics(c, p, a, seed))
for crates, seed in ((3, 2), (4, 3), (5, 4), (6, 5), (8, 6), (10, 7)):
    write(f"depot/p{crates}-{seed}.pddl", depot(crates, seed))
for f, p, seed in ((3, 2, 1), (4, 3, 2), (5, 4, 3), (8, 8, 4)):
    write(f"miconic/p{f}-{p}-{seed}.pddl", miconic(f, p, seed))
