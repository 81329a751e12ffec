; Blocks on a line: a 1-D pick-and-place domain whose positions come from streams.
; The smallest stream problem with a geometric conflict: the goal region is taken by
; another block, which must first go elsewhere. Untyped, as PDDLStream domains are.
(define (domain blocks-line)
  (:requirements :strips :equality :negative-preconditions :existential-preconditions :derived-predicates)
  (:predicates
    (Block ?b) (Region ?r)
    (Pose ?b ?p)              ; ?p is a position ?b may stand at (certified by streams)
    (Contained ?b ?p ?r)      ; standing at ?p, ?b lies inside region ?r
    (CFree ?b1 ?p1 ?b2 ?p2)   ; ?b1 at ?p1 and ?b2 at ?p2 do not overlap
    (AtPose ?b ?p) (Holding ?b) (HandEmpty)
    (Unsafe ?b ?p) (In ?b ?r))
  ; Placing ?b at ?p is unsafe when a block standing elsewhere overlaps it there.
  (:derived (Unsafe ?b ?p)
    (exists (?b2 ?p2) (and (Pose ?b ?p) (AtPose ?b2 ?p2) (not (= ?b ?b2)) (not (CFree ?b ?p ?b2 ?p2)))))
  (:derived (In ?b ?r)
    (exists (?p) (and (Contained ?b ?p ?r) (AtPose ?b ?p))))
  (:action pick
    :parameters (?b ?p)
    :precondition (and (Block ?b) (AtPose ?b ?p) (HandEmpty))
    :effect (and (Holding ?b) (not (AtPose ?b ?p)) (not (HandEmpty))))
  (:action place
    :parameters (?b ?p)
    :precondition (and (Pose ?b ?p) (Holding ?b) (not (Unsafe ?b ?p)))
    :effect (and (AtPose ?b ?p) (HandEmpty) (not (Holding ?b)))))
