; Streams of blocks-2d, all bound to the blocks_2d example plugin by the problem files.
(define (stream blocks-2d)
  (:stream sample-placement          ; poses of b inside r, drawn at random
    :inputs (?b ?r)
    :domain (Placeable ?b ?r)
    :outputs (?p)
    :certified (and (Pose ?b ?p) (Contained ?b ?p ?r)))
  (:stream test-contained            ; does b at a given pose lie inside r?
    :inputs (?b ?p ?r)
    :domain (and (Pose ?b ?p) (Placeable ?b ?r))
    :certified (Contained ?b ?p ?r))
  (:stream sample-grasp              ; suction on the block's top
    :inputs (?b)
    :domain (Block ?b)
    :outputs (?g)
    :certified (Grasp ?b ?g))
  (:stream inverse-kinematics        ; the gripper's tip where it holds b at p with g
    :inputs (?b ?p ?g)
    :domain (and (Pose ?b ?p) (Grasp ?b ?g))
    :outputs (?q)
    :certified (and (Conf ?q) (Kin ?b ?q ?p ?g)))
  (:stream plan-motion               ; up to the carry height, across, down
    :inputs (?q1 ?q2)
    :domain (and (Conf ?q1) (Conf ?q2))
    :outputs (?t)
    :certified (and (Traj ?t) (Motion ?q1 ?t ?q2)))
  (:stream test-cfree                ; do b1 at p1 and b2 at p2 keep apart?
    :inputs (?b1 ?p1 ?b2 ?p2)
    :domain (and (Pose ?b1 ?p1) (Pose ?b2 ?p2))
    :certified (CFree ?b1 ?p1 ?b2 ?p2))
  (:function (Distance ?q1 ?q2)      ; the length of that motion, m
    (and (Conf ?q1) (Conf ?q2))))
