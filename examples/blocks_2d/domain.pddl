; blocks-2d: pick and place of blocks in a vertical plane, the continuous values
; certified by the streams of stream.pddl (bound to the blocks_2d example plugin).
; A block stands on the table (y = 0) with its bottom centre at a pose [x, y]; the
; robot is a suction gripper whose configuration is its tip [x, y]; a grasp is the tip's
; offset from the pose. The robot moves between configurations (move), picks a block
; where it stands and places it where no other block stands in its way.
(define (domain blocks-2d)
  (:requirements :strips :equality :negative-preconditions :existential-preconditions
                 :derived-predicates :action-costs)
  (:predicates
    ; static: from the problem, or certified by streams
    (Block ?b) (Region ?r) (Placeable ?b ?r) (Pose ?b ?p) (Grasp ?b ?g) (Conf ?q) (Traj ?t)
    (Contained ?b ?p ?r)       ; b at p lies inside region r
    (Kin ?b ?q ?p ?g)          ; the gripper at q holds b at p with grasp g
    (Motion ?q1 ?t ?q2)        ; t moves the gripper from q1 to q2 above every block
    (CFree ?b1 ?p1 ?b2 ?p2)    ; b1 at p1 and b2 at p2 do not overlap
    ; fluent
    (AtPose ?b ?p) (AtGrasp ?b ?g) (AtConf ?q) (HandEmpty) (CanMove)
    ; derived
    (In ?b ?r) (Holding ?b) (UnsafePose ?b ?p))
  (:functions (Distance ?q1 ?q2) (total-cost))
  (:derived (In ?b ?r) (exists (?p) (and (Contained ?b ?p ?r) (AtPose ?b ?p))))
  (:derived (Holding ?b) (exists (?g) (and (Grasp ?b ?g) (AtGrasp ?b ?g))))
  ; p is unsafe for b while another block stands where b would overlap it.
  (:derived (UnsafePose ?b ?p)
    (exists (?b2 ?p2) (and (Pose ?b ?p) (Pose ?b2 ?p2) (AtPose ?b2 ?p2) (not (= ?b ?b2))
                           (not (CFree ?b ?p ?b2 ?p2)))))
  ; CanMove keeps two moves from following each other: a move goes where a pick or a
  ; place needs the gripper.
  (:action move
    :parameters (?q1 ?t ?q2)
    :precondition (and (Motion ?q1 ?t ?q2) (AtConf ?q1) (CanMove))
    :effect (and (AtConf ?q2) (not (AtConf ?q1)) (not (CanMove))
                 (increase (total-cost) (Distance ?q1 ?q2))))
  (:action pick
    :parameters (?b ?p ?g ?q)
    :precondition (and (Kin ?b ?q ?p ?g) (AtConf ?q) (AtPose ?b ?p) (HandEmpty))
    :effect (and (AtGrasp ?b ?g) (CanMove) (not (AtPose ?b ?p)) (not (HandEmpty))
                 (increase (total-cost) 1)))
  (:action place
    :parameters (?b ?p ?g ?q)
    :precondition (and (Kin ?b ?q ?p ?g) (AtConf ?q) (AtGrasp ?b ?g) (not (UnsafePose ?b ?p)))
    :effect (and (AtPose ?b ?p) (HandEmpty) (CanMove) (not (AtGrasp ?b ?g))
                 (increase (total-cost) 1))))
