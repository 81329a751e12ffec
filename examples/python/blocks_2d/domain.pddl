; Blocks on a line (a 2-D world seen from above, blocks sliding along x): pick a block
; up, put it down at a pose a stream sampled inside a region, never overlapping another
; block. Poses and regions are Python values; streams.pddl says what certifies them.
(define (domain blocks-2d)
  (:requirements :strips :equality :negative-preconditions :existential-preconditions :derived-predicates)
  (:predicates
    (Block ?b) (Region ?r) (Pose ?b ?p) (Contained ?b ?p ?r) (CFree ?b ?p ?b2 ?p2)  ; static
    (AtPose ?b ?p) (HandEmpty) (Holding ?b)                                          ; fluent
    (In ?b ?r) (Unsafe ?b ?p))                                                       ; derived
  (:derived (In ?b ?r) (exists (?p) (and (Contained ?b ?p ?r) (AtPose ?b ?p))))
  (:derived (Unsafe ?b ?p)
    (exists (?b2 ?p2) (and (Pose ?b ?p) (AtPose ?b2 ?p2) (not (= ?b ?b2)) (not (CFree ?b ?p ?b2 ?p2)))))
  (:action pick
    :parameters (?b ?p)
    :precondition (and (Block ?b) (Pose ?b ?p) (AtPose ?b ?p) (HandEmpty))
    :effect (and (Holding ?b) (not (AtPose ?b ?p)) (not (HandEmpty))))
  (:action place
    :parameters (?b ?p)
    :precondition (and (Block ?b) (Pose ?b ?p) (Holding ?b) (not (Unsafe ?b ?p)))
    :effect (and (AtPose ?b ?p) (HandEmpty) (not (Holding ?b)))))
