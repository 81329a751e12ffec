; Depots (IPC 2002), typed STRIPS: hoists load crates onto trucks and stack them on pallets.
(define (domain depot)
  (:requirements :strips :typing)
  (:types place locatable - object
          depot distributor - place
          truck hoist surface - locatable
          pallet crate - surface)
  (:predicates (at ?x - locatable ?y - place) (on ?x - crate ?y - surface) (in ?x - crate ?y - truck)
               (lifting ?x - hoist ?y - crate) (available ?x - hoist) (clear ?x - surface))
  (:action drive
    :parameters (?x - truck ?y - place ?z - place)
    :precondition (at ?x ?y)
    :effect (and (not (at ?x ?y)) (at ?x ?z)))
  (:action lift
    :parameters (?x - hoist ?y - crate ?z - surface ?p - place)
    :precondition (and (at ?x ?p) (available ?x) (at ?y ?p) (on ?y ?z) (clear ?y))
    :effect (and (not (at ?y ?p)) (lifting ?x ?y) (not (clear ?y)) (not (available ?x)) (clear ?z) (not (on ?y ?z))))
  (:action drop
    :parameters (?x - hoist ?y - crate ?z - surface ?p - place)
    :precondition (and (at ?x ?p) (at ?z ?p) (clear ?z) (lifting ?x ?y))
    :effect (and (available ?x) (not (lifting ?x ?y)) (at ?y ?p) (not (clear ?z)) (clear ?y) (on ?y ?z)))
  (:action load
    :parameters (?x - hoist ?y - crate ?z - truck ?p - place)
    :precondition (and (at ?x ?p) (at ?z ?p) (lifting ?x ?y))
    :effect (and (not (lifting ?x ?y)) (in ?y ?z) (available ?x)))
  (:action unload
    :parameters (?x - hoist ?y - crate ?z - truck ?p - place)
    :precondition (and (at ?x ?p) (at ?z ?p) (available ?x) (in ?y ?z))
    :effect (and (not (in ?y ?z)) (not (available ?x)) (lifting ?x ?y))))

;;;;
(define (problem depot-3-2)
  (:domain depot)
  (:objects depot0 - depot distributor0 distributor1 - distributor truck0 truck1 - truck pallet0 pallet1 pallet2 - pallet crate0 crate1 crate2 - crate hoist0 hoist1 hoist2 - hoist)
  (:init (at pallet0 depot0) (at hoist0 depot0) (available hoist0) (at pallet1 distributor0) (at hoist1 distributor0) (available hoist1) (at pallet2 distributor1) (at hoist2 distributor1) (available hoist2) (at truck0 depot0) (at truck1 depot0) (at crate0 depot0) (on crate0 pallet0) (at crate1 distributor0) (on crate1 pallet1) (at crate2 depot0) (on crate2 crate0) (clear crate2) (clear crate1) (clear pallet2))
  (:goal (and (on crate0 pallet1) (on crate1 pallet2))))
