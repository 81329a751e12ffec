; Pick and place among stacked objects with streams: the schemas of Tian et al.,
; T-RO 2023, Section V-C (pick needs (Clear ?o); what rests on an object must go
; first), with the paper's typos fixed (At-Pose -> AtPose, At-Grasp -> AtGrasp) and the
; continuous values - grasps, placements, trajectories - certified by the streams of
; stream.pddl. Every trajectory starts and ends at the robot's home configuration, so
; no configuration facts are needed. Collisions with the objects where they stand are
; tests: a trajectory is unsafe when it hits an object at its current pose.
(define (domain clutter-streams)
  (:requirements :strips :equality :negative-preconditions :existential-preconditions
                 :conditional-effects :derived-predicates)
  (:predicates
    ; static: from the scene, or certified by streams
    (Object ?o) (Region ?r) (Pose ?o ?p) (Grasp ?o ?g) (Traj ?t)
    (PickKin ?o ?p ?g ?t)        ; t picks o standing at p with grasp g, home to home
    (PlaceKin ?o ?p ?g ?t)       ; t puts o held with grasp g down at p, home to home
    (Placement ?o ?p ?r)         ; p is a stable pose of o inside region r
    (CFreeTrajPose ?t ?o2 ?p2)   ; t (robot and held object) misses o2 standing at p2
    (CFreePosePose ?o ?p ?o2 ?p2); o at p and o2 at p2 do not overlap
    ; fluent
    (AtPose ?o ?p) (AtGrasp ?o ?g) (HandEmpty) (On ?a ?b)
    ; derived
    (Clear ?o) (Holding ?o) (UnsafeTraj ?t) (UnsafePose ?o ?p))
  (:derived (Clear ?o) (and (Object ?o) (not (exists (?a) (On ?a ?o)))))
  (:derived (Holding ?o) (exists (?g) (AtGrasp ?o ?g)))
  (:derived (UnsafeTraj ?t)
    (exists (?o2 ?p2) (and (Traj ?t) (AtPose ?o2 ?p2) (not (CFreeTrajPose ?t ?o2 ?p2)))))
  (:derived (UnsafePose ?o ?p)
    (exists (?o2 ?p2) (and (Pose ?o ?p) (AtPose ?o2 ?p2) (not (= ?o ?o2)) (not (CFreePosePose ?o ?p ?o2 ?p2)))))
  (:action pick
    :parameters (?o ?p ?g ?t)
    :precondition (and (PickKin ?o ?p ?g ?t) (Clear ?o) (AtPose ?o ?p) (HandEmpty) (not (UnsafeTraj ?t)))
    :effect (and (AtGrasp ?o ?g) (not (AtPose ?o ?p)) (not (HandEmpty))
                 (forall (?b) (when (On ?o ?b) (not (On ?o ?b))))))
  (:action place
    :parameters (?o ?r ?p ?g ?t)
    :precondition (and (PlaceKin ?o ?p ?g ?t) (Placement ?o ?p ?r) (AtGrasp ?o ?g)
                       (not (UnsafePose ?o ?p)) (not (UnsafeTraj ?t)))
    :effect (and (AtPose ?o ?p) (On ?o ?r) (HandEmpty) (not (AtGrasp ?o ?g)))))
