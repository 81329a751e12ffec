; The pick and place schemas exactly as printed in Tian et al., Section V-C, with the
; predicates the text names. Loading it must fail: the paper writes At-Pose and AtPose,
; At-Grasp and AtGrasp for the same predicates.
(define (domain paper-verbatim)
  (:requirements :strips :negative-preconditions)
  (:predicates (Clear ?o) (AtPose ?o ?p) (HandEmpty) (AtConf ?q) (AtGrasp ?o ?g) (on ?a ?b))
  (:action pick
    :parameters (?o ?p ?g ?q)
    :precondition (and (Clear ?o) (At-Pose ?o ?p)
      (HandEmpty) (AtConf ?q))
    :effect (and (AtGrasp ?o ?g) (not (At-Pose ?o ?p))
      (not (Clear ?o)) (not (HandEmpty)))
  )
  (:action place
    :parameters (?o1 ?o2 ?p ?g ?q)
    :precondition (and (not (Clear ?o1))
      (Clear ?o2)
      (AtGrasp ?o1 ?g) (AtConf ?q))
    :effect (and (AtPose ?o1 ?p) (not (At-Grasp ?o1 ?g))
      (on ?o1 ?o2) (Clear ?o1)
      (not (Clear ?o2))
      (HandEmpty))
  )
)
