(define (problem t4p) (:domain t4) (:init (r) (= (total-cost) 0)) (:goal (and (p) (q))) (:metric minimize (total-cost)))
