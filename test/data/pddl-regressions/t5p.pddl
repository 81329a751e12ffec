(define (problem t5p) (:domain t5) (:init (= (total-cost) 0)) (:goal (g)) (:metric minimize (total-cost)))
