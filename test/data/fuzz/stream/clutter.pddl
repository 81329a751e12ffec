; Streams of clutter-streams, bound to the clutter_streams plugin by the problem file.
; Grasp, IK and motion come together: a pick's grasp is only worth having with a
; trajectory that reaches it (planned among the fixed geometry only; the tests below
; then say which objects stand in the way).
(define (stream clutter-streams)
  (:stream plan-pick
    :inputs (?o ?p)
    :domain (and (Object ?o) (Pose ?o ?p))
    :outputs (?g ?t)
    :certified (and (Grasp ?o ?g) (Traj ?t) (PickKin ?o ?p ?g ?t)))
  (:stream plan-place
    :inputs (?o ?g ?r)
    :domain (and (Grasp ?o ?g) (Region ?r))
    :outputs (?p ?t)
    :certified (and (Pose ?o ?p) (Placement ?o ?p ?r) (Traj ?t) (PlaceKin ?o ?p ?g ?t)))
  (:stream test-cfree-traj-pose
    :inputs (?t ?o2 ?p2)
    :domain (and (Traj ?t) (Pose ?o2 ?p2))
    :certified (CFreeTrajPose ?t ?o2 ?p2))
  (:stream test-cfree-pose-pose
    :inputs (?o ?p ?o2 ?p2)
    :domain (and (Pose ?o ?p) (Pose ?o2 ?p2))
    :certified (CFreePosePose ?o ?p ?o2 ?p2)))
