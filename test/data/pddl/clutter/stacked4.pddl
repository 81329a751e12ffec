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
