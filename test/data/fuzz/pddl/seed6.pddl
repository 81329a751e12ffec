; Pick and place among stacked objects: the action schemas of Tian et al., T-RO 2023,
; Section V-C, with the paper's typos fixed (At-Pose -> AtPose, At-Grasp -> AtGrasp) and
; three repairs so that the schemas mean what the text says:
;  - Clear is derived: an object is clear when nothing rests on it and it is not held
;    (the paper's pick never made the objects below a picked one clear again);
;  - pick removes the (On ?o ?b) facts of the picked object;
;  - place may put an object into a region (a table, free shelf space) that is never
;    "Clear"-ed by what lies in it, or onto a clear object.
; Untyped, as PDDLStream domains are: Object, Region, Pose, Grasp, Conf and Placement
; are static facts that streams (or a problem file) certify.
(define (domain clutter-pick-place)
  (:requirements :strips :negative-preconditions :disjunctive-preconditions :existential-preconditions
                 :conditional-effects :derived-predicates)
  (:predicates (Object ?o) (Region ?r) (Grasp ?o ?g) (Conf ?q) (Placement ?o ?p ?s)
               (AtPose ?o ?p) (AtGrasp ?o ?g) (AtConf ?q) (HandEmpty) (On ?a ?b) (Clear ?o))
  (:derived (Clear ?o)
    (and (Object ?o) (not (exists (?a) (On ?a ?o))) (not (exists (?g) (AtGrasp ?o ?g)))))
  (:action pick
    :parameters (?o ?p ?g ?q)
    :precondition (and (Object ?o) (Grasp ?o ?g) (Conf ?q)
                       (Clear ?o) (AtPose ?o ?p) (HandEmpty) (AtConf ?q))
    :effect (and (AtGrasp ?o ?g) (not (AtPose ?o ?p)) (not (HandEmpty))
                 (forall (?b) (when (On ?o ?b) (not (On ?o ?b))))))
  (:action place
    :parameters (?o1 ?o2 ?p ?g ?q)
    :precondition (and (Placement ?o1 ?p ?o2) (Conf ?q)
                       (not (Clear ?o1)) (or (Region ?o2) (Clear ?o2))
                       (AtGrasp ?o1 ?g) (AtConf ?q))
    :effect (and (AtPose ?o1 ?p) (not (AtGrasp ?o1 ?g)) (On ?o1 ?o2) (HandEmpty))))

;;;;
; Fig. 10(a) of Tian et al. in symbols: 'top' lies across 'front1' and 'front2', which
; stand on the shelf before the target. Goal: hold front1 (it must be cleared first).
(define (problem stacked-4)
  (:domain clutter-pick-place)
  (:objects target front1 front2 top shelf buffer
            p-target p-front1 p-front2 p-top b1 b2 b3 g-target g-front1 g-front2 g-top q0)
  (:init (Object target) (Object front1) (Object front2) (Object top) (Region shelf) (Region buffer)
         (Conf q0) (AtConf q0) (HandEmpty)
         (Grasp target g-target) (Grasp front1 g-front1) (Grasp front2 g-front2) (Grasp top g-top)
         (AtPose target p-target) (AtPose front1 p-front1) (AtPose front2 p-front2) (AtPose top p-top)
         (On target shelf) (On front1 shelf) (On front2 shelf) (On top front1) (On top front2)
         (Placement top b1 buffer) (Placement top b2 buffer) (Placement front1 b2 buffer)
         (Placement front2 b3 buffer) (Placement top p-top front1))
  (:goal (exists (?g) (AtGrasp front1 ?g))))
